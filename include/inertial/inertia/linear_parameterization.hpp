/// @file linear_parameterization.hpp
/// x = pi: the classical, linear parameterization (no consistency guarantee). Conventions as in
/// types.hpp.
#pragma once

#include "inertial/inertia/parameterization.hpp"

namespace inertial {

class LinearParameterization final : public Parameterization {
 public:
  std::string_view name() const override { return "linear"; }
  Vector10 ToPi(const Vector10& x, Matrix10* J_pi_x = nullptr) const override {
    if (J_pi_x != nullptr) J_pi_x->setIdentity();
    return x;
  }
  bool FromPi(const Vector10& pi, Vector10* x) const override {
    if (!pi.allFinite()) return false;
    *x = pi;
    return true;
  }
};

}  // namespace inertial
