/// @file parameterization.hpp
/// The common interface of the parameterizations compared in the paper (Section VI): a map
/// x in R^10 -> pi(x) in R^10 with its exact 10x10 Jacobian J_pi_x, and an inverse that finds an x
/// for a given pi. Implementations: LinearParameterization (x = pi), EigenvalueParameterization
/// (Section III), ExponentialParameterization (Section IV-A), LogCholeskyParameterization
/// (Section IV-B). Conventions as in types.hpp.
#pragma once

#include <string_view>

#include "inertial/inertia/types.hpp"

namespace inertial {

class Parameterization {
 public:
  virtual ~Parameterization() = default;

  /// Short stable name: "linear", "eigenvalue", "exponential", "log_cholesky".
  virtual std::string_view name() const = 0;

  /// pi(x); if J_pi_x is not null, also d(pi)/d(x) (10x10). Never allocates, never throws.
  virtual Vector10 ToPi(const Vector10& x, Matrix10* J_pi_x = nullptr) const = 0;

  /// Some x with pi(x) = pi (unique for the log-Cholesky and exponential maps; one of several for
  /// the eigenvalue map). Returns false, leaving *x untouched, when pi is outside the map's image
  /// (for the consistent parameterizations: pi not fully physically consistent) or not finite.
  virtual bool FromPi(const Vector10& pi, Vector10* x) const = 0;

  /// Whether x maps to a fully physically consistent body by construction: for the log-Cholesky and
  /// exponential maps every finite x does (even where the body is so thin that its margins round to
  /// zero); for the eigenvalue map x must have m > 0 and L > 0. The default checks the margins of
  /// pi(x) numerically (CheckConsistency), as the linear map must.
  virtual bool YieldsConsistentBody(const Vector10& x) const;
};

}  // namespace inertial
