#include "inertial/diagnosis/held_payload_fit.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <Eigen/Eigenvalues>

#include "inertial/estimation/batch/dense_levenberg_marquardt.hpp"
#include "inertial/estimation/batch/region_barrier.hpp"
#include "inertial/inertia/closed_form_bodies.hpp"
#include "inertial/model/body_region.hpp"

namespace inertial {

Vector10 PointMassPi(double m, const Vector3& c, Eigen::Matrix<double, 10, 3>* d_dc) {
  Vector10 pi;
  pi << m, m * c.x(), m * c.y(), m * c.z(), m * (c.y() * c.y() + c.z() * c.z()), m * (c.x() * c.x() + c.z() * c.z()),
      m * (c.x() * c.x() + c.y() * c.y()), -m * c.x() * c.y(), -m * c.y() * c.z(), -m * c.x() * c.z();
  if (d_dc != nullptr) {
    d_dc->setZero();
    d_dc->block<3, 3>(1, 0) = m * Matrix3::Identity();
    d_dc->row(4) << 0.0, 2 * m * c.y(), 2 * m * c.z();
    d_dc->row(5) << 2 * m * c.x(), 0.0, 2 * m * c.z();
    d_dc->row(6) << 2 * m * c.x(), 2 * m * c.y(), 0.0;
    d_dc->row(7) << -m * c.y(), -m * c.x(), 0.0;
    d_dc->row(8) << 0.0, -m * c.z(), -m * c.y();
    d_dc->row(9) << -m * c.z(), 0.0, -m * c.x();
  }
  return pi;
}

std::optional<HeldPayloadFit> FitHeldPayload(const InertialParams& estimate, const InertialParams& prior,
                                             const Matrix10& covariance, double reach) {
  const Vector10 d = estimate.vector() - prior.vector();
  // Below a micrometre no region can be drawn (nor is there a robot).
  if (!(reach > 1e-6) || !d.allFinite() || !covariance.allFinite() || !(d[0] > 0.0)) return std::nullopt;
  // Sigma^+ over Sigma's range (file comment), taken in the body's own units (kg, kg m, kg m^2 with
  // m0 = the larger of the URDF's mass and the added one, and the reach as the length) so that the
  // cut at 1e-12 compares like with like: in SI units a well-determined product of inertia
  // (variance ~1e-12 kg^2 m^4) would fall below a mass's variance times 1e-12 and go unjudged.
  const double m0 = std::max(prior.mass(), d[0]);
  Vector10 unit;
  unit << m0, m0 * reach, m0 * reach, m0 * reach, Vector6::Constant(m0 * reach * reach);
  const Matrix10 scaled = unit.cwiseInverse().asDiagonal() * (0.5 * (covariance + covariance.transpose())) *
                          unit.cwiseInverse().asDiagonal();
  const Eigen::SelfAdjointEigenSolver<Matrix10> eig(scaled);
  const double largest = eig.eigenvalues().maxCoeff();
  if (!(largest > 0.0)) return std::nullopt;
  Matrix10 W = Matrix10::Zero();
  int rank = 0;
  for (int k = 0; k < 10; ++k) {
    const double lambda = eig.eigenvalues()[k];
    if (lambda > 1e-12 * largest) {
      W.noalias() += eig.eigenvectors().col(k) * eig.eigenvectors().col(k).transpose() / lambda;
      ++rank;
    }
  }
  W = unit.cwiseInverse().asDiagonal() * W * unit.cwiseInverse().asDiagonal();
  const auto chi2_of = [&](const Vector10& phi) { return (d - phi).dot(W * (d - phi)); };
  // The payload's region as RobotDynamics gives it (body_region.hpp), about the frame origin.
  std::optional<BodyRegion> region;
  try {
    region = RegionAround(ShapePointsOfSphere(Vector3::Zero(), reach), SolidSphere(d[0], 0.01 * reach), 0.0,
                          RegionSource::kPayloadReach);
  } catch (const std::invalid_argument&) {
    return std::nullopt;
  }
  const BoundingEllipsoid& E = region->ellipsoid;
  const auto slack_of = [&](const Vector3& c) { return 1.0 - (c - E.center).dot(E.shape_inverse * (c - E.center)); };
  const double chi2_held = chi2_of(Vector10::Zero());
  // The barrier's weight: kHeldPayloadBarrierWeight of the departure to carry (scale-free, as the
  // fit's own barrier is, region_barrier.hpp): a weight in absolute chi2 units is nothing against a
  // departure of chi2 1e4, and the fit then creeps along the boundary without converging.
  const double mu = kHeldPayloadBarrierWeight * std::max(1.0, chi2_held);
  // x = (log m, c): the mass positive by construction, the COM kept inside by the barrier.
  const NormalEquationsFn problem = [&](const Eigen::VectorXd& x, double* F, Eigen::VectorXd* g, Eigen::MatrixXd* H) {
    const double m = std::exp(x[0]);
    const Vector3 c = x.segment<3>(1);
    Eigen::Matrix<double, 10, 3> d_dc;
    const Vector10 phi = PointMassPi(m, c, &d_dc);
    const double s = slack_of(c);
    const OneSidedLog b = OneSidedLogBarrier(s, kBarrierOnset);
    if (!phi.allFinite() || !std::isfinite(b.value) || !(m < region->max_mass)) return false;
    *F = 0.5 * (chi2_of(phi) + mu * b.value);
    if (g != nullptr) {
      Eigen::Matrix<double, 10, 4> J;
      J.col(0) = phi;  // d phi / d log m
      J.rightCols<3>() = d_dc;
      const Vector3 ds = -2.0 * E.shape_inverse * (c - E.center);
      Eigen::Matrix4d Hb = Eigen::Matrix4d::Zero();
      Hb.bottomRightCorner<3, 3>() = b.second * ds * ds.transpose() - 2.0 * b.first * E.shape_inverse;
      Eigen::Vector4d gb = Eigen::Vector4d::Zero();
      gb.tail<3>() = b.first * ds;
      *g = J.transpose() * (W * (phi - d)) + 0.5 * mu * gb;
      *H = J.transpose() * W * J + 0.5 * mu * Hb;
    }
    return std::isfinite(*F);
  };
  // The start: the added mass (below the region's bound) at the added first moment's COM, moved in
  // one step to within half the region's normalized radius (slack 0.75) if it lies farther out.
  Vector3 c0 = d.segment<3>(1) / d[0];
  if (!c0.allFinite()) c0 = E.center;
  const double q = (c0 - E.center).dot(E.shape_inverse * (c0 - E.center));
  if (q > 0.25) c0 = E.center + (c0 - E.center) * std::sqrt(0.25 / q);
  Eigen::VectorXd x0(4);
  x0 << std::log(std::min(d[0], 0.5 * region->max_mass)), c0;
  LevenbergMarquardtOptions lm;
  lm.max_iterations = 200;
  lm.function_tolerance = 1e-12;
  lm.step_tolerance = 1e-12;
  lm.gradient_tolerance = 1e-12;
  const DenseLevenbergMarquardtResult r = MinimizeLevenbergMarquardt(problem, x0, lm);
  const double m = std::exp(r.x[0]);
  const Vector3 c = r.x.segment<3>(1);
  const Vector10 phi = PointMassPi(m, c, nullptr);
  // Every iterate LM takes is inside (a step outside has no finite cost); a result outside would be
  // a failure of the fit, not a payload.
  if (!phi.allFinite() || !(slack_of(c) > 0.0) || !(m < region->max_mass)) return std::nullopt;
  HeldPayloadFit out;
  out.payload = InertialParams::FromVector(phi);
  out.chi2_held = chi2_held;
  out.chi2 = chi2_of(phi);
  out.rank = rank;
  out.slack = slack_of(c);
  out.region_radius = E.SemiAxes().maxCoeff();
  out.converged = r.converged();
  out.information = W;
  return out;
}

}  // namespace inertial
