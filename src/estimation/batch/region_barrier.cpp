#include "inertial/estimation/batch/region_barrier.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace inertial {
OneSidedLog OneSidedLogBarrier(double s, double s0) {
  OneSidedLog p;
  if (s >= s0) return p;
  if (!(s > 0.0)) {
    p.value = std::numeric_limits<double>::infinity();
    return p;
  }
  const double u = s / s0 - 1.0;
  p.value = -std::log(s / s0) + u - 0.5 * u * u;
  p.first = -1.0 / s + 2.0 / s0 - s / (s0 * s0);
  p.second = 1.0 / (s * s) - 1.0 / (s0 * s0);
  return p;
}

double RegionBarrier(const EstimatedBody& body, const Vector10& theta, bool newton, Vector10* g, Matrix10* H) {
  constexpr double kInfinity = std::numeric_limits<double>::infinity();
  const BodyRegion& region = *body.region;
  Matrix10 J;
  const Vector10 pi = body.map.ToPi(theta, (g != nullptr || H != nullptr) ? &J : nullptr);
  const Vector10 q = region.ellipsoid.RegionCoefficients();
  const double a = q.dot(pi), m = pi[0];
  if (!pi.allFinite() || !(a > 0.0) || !(m > 0.0) || !(m < region.max_mass)) return kInfinity;
  const double s = a / m, r = 1.0 - m / region.max_mass;
  const OneSidedLog ps = OneSidedLogBarrier(s, kBarrierOnset), pr = OneSidedLogBarrier(r, kBarrierOnset);
  const double value = ps.value + pr.value;
  if (!std::isfinite(value)) return kInfinity;
  if (g == nullptr && H == nullptr) return value;
  Vector10 e0 = Vector10::Zero();
  e0[0] = 1.0;
  const Vector10 ds = (q - s * e0) / m, dr = -e0 / region.max_mass;
  const Vector10 d_pi = ps.first * ds + pr.first * dr;
  if (g != nullptr) *g = J.transpose() * d_pi;
  if (H != nullptr) {
    Matrix10 d2_pi = ps.second * ds * ds.transpose() + pr.second * dr * dr.transpose();
    if (newton) {
      const Matrix10 d2s = -(q * e0.transpose() + e0 * q.transpose()) / (m * m) + 2.0 * a * e0 * e0.transpose() / (m * m * m);
      d2_pi += ps.first * d2s;
      *H = J.transpose() * d2_pi * J + body.map.ContractedHessian(theta, d_pi);
    } else {
      *H = J.transpose() * d2_pi * J;
    }
  }
  return value;
}

double AddRegionBarriers(const RobotDynamics& model, const Eigen::VectorXd& x, double mu, bool newton,
                         const std::vector<bool>& frozen_bodies, Eigen::VectorXd* g, Eigen::MatrixXd* H) {
  double sum = 0.0;
  Vector10 g_b;
  Matrix10 H_b;
  const bool derivatives = g != nullptr && H != nullptr;
  for (int e = 0; e < static_cast<int>(model.bodies().size()); ++e) {
    const EstimatedBody& body = model.bodies()[static_cast<size_t>(e)];
    if (!body.region || (!frozen_bodies.empty() && frozen_bodies[static_cast<size_t>(e)])) continue;
    const double b = RegionBarrier(body, x.segment<10>(10 * e), newton, derivatives ? &g_b : nullptr,
                                   derivatives ? &H_b : nullptr);
    if (!std::isfinite(b)) return std::numeric_limits<double>::infinity();
    sum += b;
    if (derivatives) {
      g->segment<10>(10 * e) += 0.5 * mu * g_b;
      H->block<10, 10>(10 * e, 10 * e) += 0.5 * mu * H_b;
    }
  }
  return sum;
}

double RegionBarrierWeight(double btb, int num_samples) {
  const double per_sample = num_samples > 0 && std::isfinite(btb) ? btb / num_samples : 0.0;
  return kRegionBarrierWeight * std::max(per_sample, 1e-12);
}

double RegionSlack(const EstimatedBody& body, const Vector10& theta) {
  if (!body.region) return std::numeric_limits<double>::infinity();
  const Vector10 pi = body.map.ToPi(theta);
  return body.region->ellipsoid.RegionCoefficients().dot(pi) / pi[0];
}

}  // namespace inertial
