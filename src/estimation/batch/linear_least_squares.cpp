#include "inertial/estimation/batch/linear_least_squares.hpp"

#include <Eigen/QR>
#include <stdexcept>

namespace inertial {

LinearLeastSquaresResult SolveLinearLeastSquares(const LinearRegression& regression) {
  if (regression.A.cols() != 10 || regression.A.rows() != regression.b.rows()) {
    throw std::invalid_argument("linear least squares: A must be N x 10 and b of length N; got A " +
                                std::to_string(regression.A.rows()) + " x " + std::to_string(regression.A.cols()) +
                                ", b " + std::to_string(regression.b.rows()));
  }
  // The complete orthogonal decomposition is the column-pivoting QR (same default threshold, so the
  // same rank) followed, when the rank is short, by an orthogonal reduction of R's first rank rows:
  // its solve is then the minimum-norm least-squares solution. ColPivHouseholderQR::solve would
  // divide by the rounding-sized pivots that rank() counts as zero. Full rank: the same solve.
  const Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod(regression.A);
  LinearLeastSquaresResult result;
  result.pi = cod.solve(regression.b);
  result.rank = static_cast<int>(cod.rank());
  result.cost = 0.5 * (regression.A * result.pi - regression.b).squaredNorm();
  return result;
}

}  // namespace inertial
