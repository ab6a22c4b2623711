/// @file linear_least_squares.hpp
/// The classical estimate: pi minimizing ||A pi - b||^2 (no consistency constraint; Atkeson et al.
/// 1986). Solved by column-pivoting Householder QR of A, completed to a complete orthogonal
/// decomposition (no normal equations, so the conditioning is that of A, not its square). When A is
/// rank deficient, pi is the minimum-norm least-squares solution. Conventions as in types.hpp.
#pragma once

#include "inertial/model/midpoint_regression.hpp"

namespace inertial {

struct LinearLeastSquaresResult {
  Vector10 pi = Vector10::Zero();  ///< the minimum-norm minimizer when rank < 10
  double cost = 0.0;  ///< 0.5 ||A pi - b||^2
  int rank = 0;       ///< numerical rank of A (10 when pi is identifiable)
};

/// @throws std::invalid_argument if A and b have inconsistent sizes or A does not have 10 columns.
LinearLeastSquaresResult SolveLinearLeastSquares(const LinearRegression& regression);

}  // namespace inertial
