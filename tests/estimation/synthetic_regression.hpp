/// @file synthetic_regression.hpp
/// Test helper: a well-excited single-body regression with exact wrenches plus Gaussian noise.
#pragma once

#include "inertial/inertia/inertial_params.hpp"
#include "inertial/model/midpoint_regression.hpp"
#include "inertial/model/rigid_body_regressor.hpp"
#include "test_support.hpp"

namespace inertial::testing {

// A well-excited regression: random twists and accelerations, exact wrenches of `body` plus noise.
inline LinearRegression SyntheticRegression(Rng& rng, const InertialParams& body, int rows6, double noise) {
  LinearRegression reg;
  reg.A.resize(6 * rows6, 10);
  reg.b.resize(6 * rows6);
  for (int i = 0; i < rows6; ++i) {
    const Matrix6x10 Y = RigidBodyRegressor(rng.UniformVector<6>(-2, 2), rng.UniformVector<6>(-2, 2));
    reg.A.block<6, 10>(6 * i, 0) = Y;
    Vector6 n;
    for (int k = 0; k < 6; ++k) n[k] = rng.Normal(noise);
    reg.b.segment<6>(6 * i) = Y * body.vector() + n;
  }
  return reg;
}

}  // namespace inertial::testing
