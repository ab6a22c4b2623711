// Recursive Gauss-Newton: on a model linear in x it is the batch regularized least squares
// (w = (P0^-1 + A^T A / s^2)^-1 (P0^-1 x0 + A^T y / s^2)); through an exponential block one sample is
// the extended Kalman step with H = A diag(e^x); steps beyond max_abs_parameter are refused.
#include "inertial/estimation/online/recursive_gauss_newton.hpp"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <limits>

#include "estimation/synthetic_regression.hpp"
#include "test_support.hpp"

namespace inertial {
namespace {

using testing::RandomMatrix;
using testing::Rng;
using testing::Scalars;

constexpr double kInf = std::numeric_limits<double>::infinity();

RecursiveGaussNewtonOptions Plain(double sigma) {
  RecursiveGaussNewtonOptions o;
  o.kalman.measurement_sigma = sigma;
  o.kalman.huber = o.kalman.gate = o.kalman.max_step = kInf;
  return o;
}

TEST(RecursiveGaussNewton, LinearModelEqualsBatchRegularizedLeastSquares) {
  Rng rng(1);
  const int n = 5, m = 2, N = 200;
  const double sigma = 0.2;
  Eigen::VectorXd x0(n), std0(n), truth(n);
  for (int i = 0; i < n; ++i) {
    x0[i] = rng.Normal();
    std0[i] = rng.Uniform(0.5, 2.0);
    truth[i] = rng.Normal(2.0);
  }
  RecursiveGaussNewton rgn(Scalars(n, ScalarMap::kLinear), m, x0, std0, Plain(sigma));
  Eigen::MatrixXd normal = std0.array().square().inverse().matrix().asDiagonal();
  Eigen::VectorXd rhs = normal * x0;
  for (int k = 0; k < N; ++k) {
    const Eigen::MatrixXd A = RandomMatrix(rng, m, n);
    Eigen::VectorXd y = A * truth;
    for (int i = 0; i < m; ++i) y[i] += rng.Normal(sigma);
    ASSERT_EQ(rgn.Update(0.01 * k, A, y), UpdateStatus::kAccepted);
    normal += A.transpose() * A / (sigma * sigma);
    rhs += A.transpose() * y / (sigma * sigma);
  }
  const Eigen::VectorXd batch = normal.ldlt().solve(rhs);
  EXPECT_LT((rgn.parameters() - batch).norm() / batch.norm(), 1e-10);
  EXPECT_LT((rgn.Covariance() - Eigen::MatrixXd(normal.inverse())).norm() / normal.inverse().norm(), 1e-9);
  EXPECT_EQ(rgn.kind(), "ekf");
}

TEST(RecursiveGaussNewton, ExponentialBlockTakesTheExtendedKalmanStep) {
  Rng rng(2);
  const int n = 3, m = 2;
  const double sigma = 0.5;
  const Eigen::Vector3d x0(0.1, -0.3, 0.2), std0(0.3, 0.2, 0.4);
  RecursiveGaussNewton rgn(Scalars(n, ScalarMap::kExponential), m, x0, std0, Plain(sigma));
  const Eigen::MatrixXd A = RandomMatrix(rng, m, n);
  const Eigen::Vector3d w0 = x0.array().exp();
  const Eigen::VectorXd y = A * w0 + 0.3 * RandomMatrix(rng, m, 1);
  const Eigen::MatrixXd H = A * w0.asDiagonal();
  const Eigen::MatrixXd P = std0.array().square().matrix().asDiagonal();
  const Eigen::MatrixXd S = H * P * H.transpose() + sigma * sigma * Eigen::MatrixXd::Identity(m, m);
  const Eigen::MatrixXd K = P * H.transpose() * S.inverse();
  ASSERT_EQ(rgn.Update(0.0, A, y), UpdateStatus::kAccepted);
  EXPECT_LT((rgn.parameters() - (x0 + K * (y - A * w0))).norm(), 1e-13);
  EXPECT_LT((rgn.Covariance() - (P - K * H * P)).norm(), 1e-13);
  EXPECT_NEAR(rgn.normalized_innovation(), std::sqrt((y - A * w0).dot(S.inverse() * (y - A * w0)) / m), 1e-12);
  Eigen::VectorXd w(n);
  rgn.Coefficients(w);
  EXPECT_LT((w - Eigen::VectorXd(rgn.parameters().array().exp())).norm(), 1e-14);
}

TEST(RecursiveGaussNewton, StepsBeyondTheParameterBoundAreRefused) {
  RecursiveGaussNewtonOptions o = Plain(0.01);
  o.max_abs_parameter = 1.0;
  RecursiveGaussNewton rgn(Scalars(1, ScalarMap::kLinear), 1, Eigen::VectorXd::Zero(1), Eigen::VectorXd::Ones(1), o);
  const Eigen::MatrixXd A = Eigen::MatrixXd::Identity(1, 1);
  EXPECT_EQ(rgn.Update(0.0, A, Eigen::VectorXd::Constant(1, 5.0)), UpdateStatus::kNumerical);  // x would be ~5
  EXPECT_EQ(rgn.parameters()[0], 0.0);
  EXPECT_EQ(rgn.Covariance()(0, 0), 1.0);  // nothing committed
  ASSERT_EQ(rgn.Update(1.0, A, Eigen::VectorXd::Constant(1, 0.5)), UpdateStatus::kAccepted);
  EXPECT_NEAR(rgn.parameters()[0], 0.5 / (1.0 + 1e-4), 1e-15);
}

}  // namespace
}  // namespace inertial
