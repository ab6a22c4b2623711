#include "inertial/inertia/plausibility.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace inertial {

double BodyPlausibility::Excess(double tolerance) const {
  return std::max(0.0, std::log(factor) - std::log1p(tolerance));
}

namespace {

// x moved toward 0 by margin, not past it.
double Shrunk(double x, double margin) {
  if (!(margin < std::numeric_limits<double>::infinity())) return 0.0;
  return std::abs(x) <= margin ? 0.0 : x - std::copysign(margin, x);
}

}  // namespace

BodyPlausibility MeasurePlausibility(const InertialParams& body, const InertialParams& prior,
                                     const DepartureMargins& margins) {
  const Matrix4 J = body.pseudo_inertia();
  const Matrix4 J0 = prior.pseudo_inertia();
  const Eigen::LLT<Matrix4> l0(J0);
  if (!J.allFinite() || !J0.allFinite() || l0.info() != Eigen::Success || Eigen::LLT<Matrix4>(J).info() != Eigen::Success) {
    throw std::invalid_argument("plausibility: both bodies must have positive definite pseudo-inertias");
  }
  // J v = lambda J0 v with J0 = L L^T: eigenvalues of L^-1 J L^-T (symmetric).
  const Matrix4 Linv = l0.matrixL().solve(Matrix4::Identity());
  const Matrix4 S = Linv * J * Linv.transpose();
  const Eigen::SelfAdjointEigenSolver<Matrix4> eig(0.5 * (S + S.transpose()), Eigen::EigenvaluesOnly);
  BodyPlausibility p;
  p.lambda = eig.eigenvalues();
  p.divergence = 0.0;
  for (int i = 0; i < 4; ++i) p.divergence += p.lambda[i] - 1.0 - std::log(p.lambda[i]);
  p.mass_ratio = body.mass() / prior.mass();
  p.com_shift = (body.com() - prior.com()).norm();
  // Sigma0 about the COM is the top-left block of J0 less m0 c0 c0^T; its trace is tr(I_c0) / 2.
  const Matrix3 I0 = prior.rotational_inertia_about_com();
  const double rho0 = std::sqrt(0.5 * I0.trace() / prior.mass());
  p.com_shift_relative = p.com_shift / rho0;
  const Vector3 h = body.mass() * (body.com() - prior.com());  // first moment about the prior's COM
  const double scale = prior.mass() * rho0;
  p.first_moment_change = h.norm() / scale;
  const Matrix3 I = body.rotational_inertia_about_com();
  const Eigen::SelfAdjointEigenSolver<Matrix3> a(I, Eigen::EigenvaluesOnly);
  const Eigen::SelfAdjointEigenSolver<Matrix3> b(I0, Eigen::EigenvaluesOnly);
  p.moment_ratios = a.eigenvalues().cwiseQuotient(b.eigenvalues());
  const Eigen::SelfAdjointEigenSolver<Matrix3> change(I - I0, Eigen::EigenvaluesOnly);
  p.inertia_change = change.eigenvalues().cwiseAbs().maxCoeff() / b.eigenvalues().maxCoeff();
  p.raw_factor = std::max({p.mass_ratio, 1.0 / p.mass_ratio, 1.0 + p.first_moment_change, 1.0 + p.inertia_change});
  // Beyond the margins.
  const double m = prior.mass() + Shrunk(body.mass() - prior.mass(), margins.mass);
  double kept_h = 0.0;
  if (h.norm() > 0.0) {
    const Vector3 u = h / h.norm();
    const double along = std::sqrt(std::max(0.0, u.dot(margins.first_moment * u)));
    kept_h = std::isfinite(along) ? std::max(0.0, h.norm() - along) : 0.0;
  }
  const Matrix3 dI = I - I0;
  const int row[6] = {0, 1, 2, 0, 1, 0}, col[6] = {0, 1, 2, 1, 2, 2};
  Matrix3 kept = Matrix3::Zero();
  for (int k = 0; k < 6; ++k) {
    kept(row[k], col[k]) = kept(col[k], row[k]) = Shrunk(dI(row[k], col[k]), margins.inertia_about_com[k]);
  }
  const double kept_change = Eigen::SelfAdjointEigenSolver<Matrix3>(kept, Eigen::EigenvaluesOnly)
                                 .eigenvalues().cwiseAbs().maxCoeff() / b.eigenvalues().maxCoeff();
  p.factor = std::max({m / prior.mass(), prior.mass() / m, 1.0 + kept_h / scale, 1.0 + kept_change});
  return p;
}

}  // namespace inertial
