/// @file positive_eigenvalue_parameterization.hpp
/// The eigenvalue construction (Section III) with its positive quantities exponentiated:
///   x = [mu, cx, cy, cz, beta1, beta2, beta3, lx, ly, lz],  m = e^mu,  L = e^l,
/// and pi = EigenvalueParameterization::ToPi([m, c, beta, L]). Every finite x gives a fully
/// consistent body, as Section VI requires of the three nonlinear parameterizations it compares
/// ("they ensure that the result is physically consistent"); without the exponentials, m and L are
/// free to go negative and the optimizer simply returns the nonphysical linear solution. The
/// symmetry singularity of Section III-A is unchanged: det(J_pi_x) = det(J_pi_phi) m Lx Ly Lz still
/// has the factors (Lx - Ly)(Ly - Lz)(Lx - Lz). Conventions as in eigenvalue_parameterization.hpp.
#pragma once

#include "inertial/inertia/eigenvalue_parameterization.hpp"

namespace inertial {

class PositiveEigenvalueParameterization final : public Parameterization {
 public:
  std::string_view name() const override { return "eigenvalue"; }
  Vector10 ToPi(const Vector10& x, Matrix10* J_pi_x = nullptr) const override;
  /// Some x with pi(x) = pi: false if pi is not fully consistent (as EigenvalueParameterization).
  bool FromPi(const Vector10& pi, Vector10* x) const override;
  /// Every finite x whose pi is finite.
  bool YieldsConsistentBody(const Vector10& x) const override;

  /// phi = [e^mu, c, beta, e^l] and back.
  static Vector10 PhiFromX(const Vector10& x);

 private:
  EigenvalueParameterization eigenvalue_;
};

}  // namespace inertial
