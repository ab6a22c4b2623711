// Linear recursive least squares, the unconstrained baseline: without forgetting and robust
// weighting it is exactly the batch regularized least squares.
#include "inertial/estimation/online/linear_rls.hpp"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <limits>

#include "test_support.hpp"

namespace inertial {
namespace {

using testing::Rng;

// With no forgetting and no robust weighting, recursive least squares is exactly the batch
// regularized least squares: w = (P0^-1 + A^T A / s^2)^-1 (P0^-1 w0 + A^T y / s^2).
TEST(LinearRls, EqualsBatchRegularizedLeastSquares) {
  Rng rng(32);
  const int n = 10, m = 6, N = 300;
  const double sigma = 0.3;
  Eigen::VectorXd w0(n), std0(n), truth(n);
  for (int i = 0; i < n; ++i) {
    w0[i] = rng.Normal();
    std0[i] = rng.Uniform(0.5, 2.0);
    truth[i] = rng.Normal(3.0);
  }
  KalmanOptions o;
  o.measurement_sigma = sigma;
  o.huber = o.gate = std::numeric_limits<double>::infinity();
  o.max_step = std::numeric_limits<double>::infinity();
  LinearRls rls(m, w0, std0, o);
  Eigen::MatrixXd normal = std0.array().square().inverse().matrix().asDiagonal();
  Eigen::VectorXd rhs = normal * w0;
  for (int k = 0; k < N; ++k) {
    Eigen::MatrixXd A(m, n);
    for (int i = 0; i < A.size(); ++i) A.data()[i] = rng.Normal();
    Eigen::VectorXd y = A * truth;
    for (int i = 0; i < m; ++i) y[i] += rng.Normal(sigma);
    ASSERT_EQ(rls.Update(0.01 * k, A, y), UpdateStatus::kAccepted);
    normal += A.transpose() * A / (sigma * sigma);
    rhs += A.transpose() * y / (sigma * sigma);
  }
  const Eigen::VectorXd batch = normal.ldlt().solve(rhs);
  EXPECT_LT((rls.parameters() - batch).norm() / batch.norm(), 1e-10);
  EXPECT_LT((rls.Covariance() - Eigen::MatrixXd(normal.inverse())).norm() / normal.inverse().norm(), 1e-9);
}

}  // namespace
}  // namespace inertial
