// The normalized gradient law: one step against its formula dx = gain Gamma H^T r / (sigma^2 +
// sum_j Gamma_j |H_:j|^2) (with w = x, and through an exponential block with H = A diag(e^x)), the
// Huber scaling, the step bound and the outlier gate, convergence on exact linear data, and
// refusals.
#include "inertial/estimation/online/gradient_estimator.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "estimation/synthetic_regression.hpp"
#include "test_support.hpp"

namespace inertial {
namespace {

using testing::RandomMatrix;
using testing::Rng;
using testing::Scalars;

TEST(GradientEstimator, OneStepIsTheNormalizedGradient) {
  Rng rng(1);
  const int n = 4, m = 3;
  GradientOptions o;
  o.gain = 0.3;
  o.measurement_sigma = 0.5;
  o.huber = o.gate = 1e9;
  o.max_step = 1e9;
  for (ScalarMap map : {ScalarMap::kLinear, ScalarMap::kExponential}) {
    const Eigen::VectorXd x0 = 0.2 * RandomMatrix(rng, n, 1);
    const Eigen::Vector4d scale(0.5, 1.0, 1.5, 2.0);
    GradientEstimator g(Scalars(n, map), m, x0, scale, o);
    const Eigen::MatrixXd A = RandomMatrix(rng, m, n);
    const Eigen::VectorXd y = RandomMatrix(rng, m, 1);
    const Eigen::VectorXd w = map == ScalarMap::kLinear ? x0 : Eigen::VectorXd(x0.array().exp());
    const Eigen::MatrixXd H = map == ScalarMap::kLinear ? A : Eigen::MatrixXd(A * w.asDiagonal());  // dw/dx = e^x
    const Eigen::VectorXd r = y - A * w;
    const Eigen::Vector4d gamma = scale.array().square();
    const double norm = 0.25 + (H.colwise().squaredNorm().transpose().array() * gamma.array()).sum();
    const Eigen::VectorXd dx = 0.3 * gamma.cwiseProduct(H.transpose() * r) / norm;
    ASSERT_EQ(g.Update(0.0, A, y), UpdateStatus::kAccepted);
    EXPECT_LT((g.parameters() - (x0 + dx)).norm(), 1e-14) << static_cast<int>(map);
    Eigen::VectorXd coefficients(n);
    g.Coefficients(coefficients);
    if (map == ScalarMap::kExponential) {
      EXPECT_TRUE((coefficients.array() > 0).all());
    }
  }
}

// Beyond the Huber threshold the residual is scaled to it; the step is bounded; beyond the gate the
// sample is refused and nothing changes.
TEST(GradientEstimator, HuberScalingStepBoundAndGate) {
  GradientOptions o;
  o.gain = 1.0;
  o.measurement_sigma = 1.0;
  o.huber = 2.0;
  o.gate = 50.0;
  o.max_step = 10.0;
  const Eigen::MatrixXd A = Eigen::MatrixXd::Identity(1, 1);
  GradientEstimator g(Scalars(1, ScalarMap::kLinear), 1, Eigen::VectorXd::Zero(1), Eigen::VectorXd::Ones(1), o);
  // r = 8 (e = 8 > 2): scaled to 2, dx = 1 * 2 / (1 + 1) = 1.
  ASSERT_EQ(g.Update(0.0, A, Eigen::VectorXd::Constant(1, 8.0)), UpdateStatus::kAccepted);
  EXPECT_DOUBLE_EQ(g.parameters()[0], 1.0);
  // r = 100 - 1 = 99 > gate: refused.
  EXPECT_EQ(g.Update(1.0, A, Eigen::VectorXd::Constant(1, 100.0)), UpdateStatus::kOutlier);
  EXPECT_DOUBLE_EQ(g.parameters()[0], 1.0);
  o.huber = 1e9;
  o.max_step = 0.25;
  GradientEstimator bounded(Scalars(1, ScalarMap::kLinear), 1, Eigen::VectorXd::Zero(1), Eigen::VectorXd::Ones(1), o);
  ASSERT_EQ(bounded.Update(0.0, A, Eigen::VectorXd::Constant(1, 8.0)), UpdateStatus::kAccepted);  // 4 -> 0.25
  EXPECT_DOUBLE_EQ(bounded.parameters()[0], 0.25);
  o.max_step = 1e9;
  o.max_abs_parameter = 1.0;
  GradientEstimator limited(Scalars(1, ScalarMap::kLinear), 1, Eigen::VectorXd::Zero(1), Eigen::VectorXd::Ones(1), o);
  EXPECT_EQ(limited.Update(0.0, A, Eigen::VectorXd::Constant(1, 8.0)), UpdateStatus::kNumerical);  // x would be 4
  EXPECT_DOUBLE_EQ(limited.parameters()[0], 0.0);
}

TEST(GradientEstimator, ConvergesOnExactLinearData) {
  Rng rng(2);
  const int n = 3, m = 2;
  const Eigen::Vector3d truth(0.4, -0.7, 1.1);
  GradientOptions o;
  o.gain = 0.5;
  o.measurement_sigma = 0.01;
  o.huber = o.gate = 1e9;  // exact data: no sample is an outlier however far the start
  GradientEstimator g(Scalars(n, ScalarMap::kLinear), m, Eigen::VectorXd::Zero(n), Eigen::VectorXd::Ones(n), o);
  for (int k = 0; k < 3000; ++k) {
    const Eigen::MatrixXd A = RandomMatrix(rng, m, n);
    ASSERT_EQ(g.Update(0.01 * k, A, A * truth), UpdateStatus::kAccepted);
  }
  EXPECT_LT((g.parameters() - truth).norm(), 1e-8);
  EXPECT_EQ(g.Covariance().size(), 0);  // the law keeps no covariance
  EXPECT_EQ(g.kind(), "gradient");
}

TEST(GradientEstimator, RefusesBadConstruction) {
  const ParameterLayout layout = Scalars(2, ScalarMap::kLinear);
  EXPECT_THROW(GradientEstimator(layout, 1, Eigen::VectorXd::Zero(3), Eigen::VectorXd::Ones(2)), std::invalid_argument);
  EXPECT_THROW(GradientEstimator(layout, 1, Eigen::VectorXd::Zero(2), Eigen::Vector2d(1.0, 0.0)), std::invalid_argument);
  EXPECT_THROW(GradientEstimator(layout, 1, Eigen::Vector2d(std::nan(""), 0.0), Eigen::VectorXd::Ones(2)), std::invalid_argument);
  GradientOptions o;
  o.gain = 2.5;
  EXPECT_THROW(GradientEstimator(layout, 1, Eigen::VectorXd::Zero(2), Eigen::VectorXd::Ones(2), o), std::invalid_argument);
}

}  // namespace
}  // namespace inertial
