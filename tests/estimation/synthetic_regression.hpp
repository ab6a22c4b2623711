/// @file synthetic_regression.hpp
/// Test helpers for the estimators' tests: a well-excited single-body regression with exact
/// wrenches plus Gaussian noise, a layout of scalar blocks, and a seeded Gaussian matrix.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "inertial/estimation/parameter_layout.hpp"
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
    // One draw per statement, xi_dot first, as the x86-64 build drew them (see Rng).
    const Vector6 xi_dot = rng.UniformVector<6>(-2, 2);
    const Matrix6x10 Y = RigidBodyRegressor(rng.UniformVector<6>(-2, 2), xi_dot);
    reg.A.block<6, 10>(6 * i, 0) = Y;
    Vector6 n;
    for (int k = 0; k < 6; ++k) n[k] = rng.Normal(noise);
    reg.b.segment<6>(6 * i) = Y * body.vector() + n;
  }
  return reg;
}

// n scalar parameters, each its own block with map `map` (parameter i is coefficient i).
inline ParameterLayout Scalars(int n, ScalarMap map) {
  std::vector<ScalarBlock> blocks;
  for (int i = 0; i < n; ++i) blocks.push_back(ScalarBlock{map, i, i});
  return ParameterLayout(n, {}, blocks);
}

// A rows x cols matrix of independent standard normal draws.
inline Eigen::MatrixXd RandomMatrix(Rng& rng, int rows, int cols) {
  Eigen::MatrixXd M(rows, cols);
  for (int i = 0; i < M.size(); ++i) M.data()[i] = rng.Normal();
  return M;
}

}  // namespace inertial::testing
