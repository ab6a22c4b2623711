#include "inertial/inertia/positive_eigenvalue_parameterization.hpp"

#include <cmath>

namespace inertial {

Vector10 PositiveEigenvalueParameterization::PhiFromX(const Vector10& x) {
  Vector10 phi = x;
  phi[phi_index::kMass] = std::exp(x[phi_index::kMass]);
  for (int k = phi_index::kLx; k <= phi_index::kLz; ++k) phi[k] = std::exp(x[k]);
  return phi;
}

Vector10 PositiveEigenvalueParameterization::ToPi(const Vector10& x, Matrix10* J_pi_x) const {
  const Vector10 phi = PhiFromX(x);
  const Vector10 pi = eigenvalue_.ToPi(phi, J_pi_x);
  if (J_pi_x != nullptr) {
    // Chain rule: d(phi_k)/d(x_k) = phi_k for the exponentiated entries, 1 otherwise.
    J_pi_x->col(phi_index::kMass) *= phi[phi_index::kMass];
    for (int k = phi_index::kLx; k <= phi_index::kLz; ++k) J_pi_x->col(k) *= phi[k];
  }
  return pi;
}

bool PositiveEigenvalueParameterization::FromPi(const Vector10& pi, Vector10* x) const {
  Vector10 phi;
  if (!eigenvalue_.FromPi(pi, &phi)) return false;
  Vector10 result = phi;
  result[phi_index::kMass] = std::log(phi[phi_index::kMass]);
  for (int k = phi_index::kLx; k <= phi_index::kLz; ++k) result[k] = std::log(phi[k]);
  if (!result.allFinite()) return false;
  *x = result;
  return true;
}

bool PositiveEigenvalueParameterization::YieldsConsistentBody(const Vector10& x) const {
  return x.allFinite() && eigenvalue_.YieldsConsistentBody(PhiFromX(x));
}

}  // namespace inertial
