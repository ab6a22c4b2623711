/// @file midpoint_regression.hpp
/// The paper's second-order discretization of eq. (12) from sampled twists (eq. 13): for each pair
/// of samples (i, i+1),
///   xi_dot_i = (xi_{i+1} - xi_i) / (t_{i+1} - t_i),   xi_bar_i = (xi_{i+1} + xi_i) / 2,
///   r_i = I xi_dot_i + xi_bar_i x* I xi_bar_i - w_i = Y(xi_bar_i, xi_dot_i) pi - w_i,
/// with w_i the wrench at the midpoint, taken as (w_i + w_{i+1}) / 2 (second order, like the
/// rest of the implicit-midpoint rule; the paper writes w_i without saying which).
/// Stacking all pairs gives the linear system r = A pi - b used by every estimator.
/// Conventions: twist [omega; v], wrench [moment; force], body coordinates, SI units.
#pragma once

#include <string>
#include <vector>

#include "inertial/inertia/types.hpp"

namespace inertial {

/// One single-body measurement: time [s], body twist, applied wrench (excluding gravity).
struct TwistWrenchSample {
  double t = 0.0;
  Vector6 twist = Vector6::Zero();
  Vector6 wrench = Vector6::Zero();
};

/// Residual model r = A pi - b, 6 rows per sample pair.
struct LinearRegression {
  Eigen::MatrixXd A;  ///< 6 (N-1) x 10
  Eigen::VectorXd b;  ///< 6 (N-1)
};

/// The regressor block and wrench of one pair (eq. 13). Allocation-free. Precondition: t1 > t0.
void MidpointRegressorPair(const TwistWrenchSample& s0, const TwistWrenchSample& s1, const Vector3& g_B,
                           Matrix6x10* Y, Vector6* w);

/// Stacks every pair. Validates the input.
/// @throws std::invalid_argument naming the sample index and the problem if there are fewer than
/// two samples, a value is not finite, or time does not strictly increase.
LinearRegression BuildMidpointRegression(const std::vector<TwistWrenchSample>& samples,
                                         const Vector3& g_B = Vector3::Zero());

}  // namespace inertial
