#include "inertial/diagnosis/held_payload_fit.hpp"

#include <cmath>

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
  if (!(reach > 0.0) || !d.allFinite() || !covariance.allFinite() || !(d[0] > 0.0)) return std::nullopt;
  // Sigma^+ over Sigma's range (file comment).
  const Eigen::SelfAdjointEigenSolver<Matrix10> eig(0.5 * (covariance + covariance.transpose()));
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
  const auto chi2_of = [&](const Vector10& phi) { return (d - phi).dot(W * (d - phi)); };
  // The payload's region as RobotDynamics gives it (body_region.hpp), about the frame origin.
  const BodyRegion region = RegionAround(ShapePointsOfSphere(Vector3::Zero(), reach), SolidSphere(d[0], 0.01 * reach),
                                         0.0, RegionSource::kPayloadReach);
  const BoundingEllipsoid& E = region.ellipsoid;
  const auto slack_of = [&](const Vector3& c) { return 1.0 - (c - E.center).dot(E.shape_inverse * (c - E.center)); };
  const double mu = kHeldPayloadBarrierWeight;
  // x = (log m, c): the mass positive by construction, the COM kept inside by the barrier.
  const NormalEquationsFn problem = [&](const Eigen::VectorXd& x, double* F, Eigen::VectorXd* g, Eigen::MatrixXd* H) {
    const double m = std::exp(x[0]);
    const Vector3 c = x.segment<3>(1);
    Eigen::Matrix<double, 10, 3> d_dc;
    const Vector10 phi = PointMassPi(m, c, &d_dc);
    const double s = slack_of(c);
    const OneSidedLog b = OneSidedLogBarrier(s, kBarrierOnset);
    if (!phi.allFinite() || !std::isfinite(b.value) || !(m < region.max_mass)) return false;
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
  // The start: the added mass at the added first moment's COM, pulled to within half the region.
  Vector3 c0 = d.segment<3>(1) / d[0];
  if (!c0.allFinite()) c0.setZero();
  for (int k = 0; k < 60 && slack_of(c0) < 0.75; ++k) c0 *= 0.9;
  Eigen::VectorXd x0(4);
  x0 << std::log(d[0]), c0;
  LevenbergMarquardtOptions lm;
  lm.max_iterations = 200;
  lm.function_tolerance = 1e-12;
  lm.step_tolerance = 1e-12;
  lm.gradient_tolerance = 1e-12;
  lm.scaled_damping = true;
  const DenseLevenbergMarquardtResult r = MinimizeLevenbergMarquardt(problem, x0, lm);
  const double m = std::exp(r.x[0]);
  const Vector3 c = r.x.segment<3>(1);
  const Vector10 phi = PointMassPi(m, c, nullptr);
  if (!phi.allFinite()) return std::nullopt;
  HeldPayloadFit out;
  out.payload = InertialParams::FromVector(phi);
  out.chi2_held = d.dot(W * d);
  out.chi2 = chi2_of(phi);
  out.rank = rank;
  out.slack = slack_of(c);
  out.converged = r.converged();
  return out;
}

}  // namespace inertial
