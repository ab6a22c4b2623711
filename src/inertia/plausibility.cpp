#include "inertial/inertia/plausibility.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace inertial {

double BodyPlausibility::Excess(double tolerance) const {
  return std::max(0.0, std::log(factor) - std::log1p(tolerance));
}

BodyPlausibility MeasurePlausibility(const InertialParams& body, const InertialParams& prior) {
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
  p.factor = 1.0;
  for (int i = 0; i < 4; ++i) {
    const double l = p.lambda[i];
    p.divergence += l - 1.0 - std::log(l);
    p.factor = std::max(p.factor, std::max(l, 1.0 / l));
  }
  p.mass_ratio = body.mass() / prior.mass();
  p.com_shift = (body.com() - prior.com()).norm();
  const Eigen::SelfAdjointEigenSolver<Matrix3> a(body.rotational_inertia_about_com(), Eigen::EigenvaluesOnly);
  const Eigen::SelfAdjointEigenSolver<Matrix3> b(prior.rotational_inertia_about_com(), Eigen::EigenvaluesOnly);
  p.moment_ratios = a.eigenvalues().cwiseQuotient(b.eigenvalues());
  return p;
}

}  // namespace inertial
