#include "inertial/estimation/linear_least_squares.hpp"

#include <Eigen/QR>
#include <stdexcept>

namespace inertial {

LinearLeastSquaresResult SolveLinearLeastSquares(const LinearRegression& regression) {
  if (regression.A.cols() != 10 || regression.A.rows() != regression.b.rows()) {
    throw std::invalid_argument("linear least squares: A must be N x 10 and b of length N; got A " +
                                std::to_string(regression.A.rows()) + " x " + std::to_string(regression.A.cols()) +
                                ", b " + std::to_string(regression.b.rows()));
  }
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(regression.A);
  LinearLeastSquaresResult result;
  result.pi = qr.solve(regression.b);
  result.rank = static_cast<int>(qr.rank());
  result.cost = 0.5 * (regression.A * result.pi - regression.b).squaredNorm();
  return result;
}

}  // namespace inertial
