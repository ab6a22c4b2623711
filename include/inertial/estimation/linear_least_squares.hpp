/// @file linear_least_squares.hpp
/// The classical estimate: pi minimizing ||A pi - b||^2 (no consistency constraint; Atkeson et al.
/// 1986). Solved by column-pivoting Householder QR of A (no normal equations, so the conditioning is
/// that of A, not its square). Conventions as in types.hpp.
#pragma once

#include "inertial/model/midpoint_regression.hpp"

namespace inertial {

struct LinearLeastSquaresResult {
  Vector10 pi = Vector10::Zero();
  double cost = 0.0;  ///< 0.5 ||A pi - b||^2
  int rank = 0;       ///< numerical rank of A (10 when pi is identifiable)
};

/// @throws std::invalid_argument if A and b have inconsistent sizes or A does not have 10 columns.
LinearLeastSquaresResult SolveLinearLeastSquares(const LinearRegression& regression);

}  // namespace inertial
