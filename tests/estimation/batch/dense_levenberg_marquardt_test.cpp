// Levenberg-Marquardt on normal equations: Rosenbrock's valley as a least-squares problem (minimum
// at (1, 1), cost 0), a linear problem whose minimum is the normal equations' solution, the cost
// history, and refusals.
#include "inertial/estimation/batch/dense_levenberg_marquardt.hpp"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <limits>
#include <stdexcept>

#include "test_support.hpp"

namespace inertial {
namespace {

// r(x) = (10 (x1 - x0^2), 1 - x0), J = [[-20 x0, 10], [-1, 0]].
bool Rosenbrock(const Eigen::VectorXd& x, double* F, Eigen::VectorXd* g, Eigen::MatrixXd* H) {
  Eigen::VectorXd r(2);
  r << 10 * (x[1] - x[0] * x[0]), 1 - x[0];
  Eigen::MatrixXd J(2, 2);
  J << -20 * x[0], 10, -1, 0;
  *F = 0.5 * r.squaredNorm();
  if (g != nullptr) *g = J.transpose() * r;
  if (H != nullptr) *H = J.transpose() * J;
  return true;
}

LevenbergMarquardtOptions Tight() {
  LevenbergMarquardtOptions o;
  o.max_iterations = 500;
  o.function_tolerance = o.step_tolerance = o.gradient_tolerance = 1e-15;
  return o;
}

TEST(DenseLevenbergMarquardt, FindsRosenbrocksMinimum) {
  const DenseLevenbergMarquardtResult r = MinimizeLevenbergMarquardt(Rosenbrock, Eigen::Vector2d(-1.2, 1.0), Tight());
  EXPECT_TRUE(r.converged()) << ToString(r.reason);
  EXPECT_LT((r.x - Eigen::Vector2d(1.0, 1.0)).norm(), 1e-7);
  EXPECT_LT(r.cost, 1e-14);
  EXPECT_DOUBLE_EQ(r.initial_cost, 0.5 * (4.4 * 4.4 + 2.2 * 2.2));  // r(-1.2, 1) = (-4.4, 2.2)
  ASSERT_FALSE(r.cost_history.empty());
  EXPECT_DOUBLE_EQ(r.cost_history.front(), r.initial_cost);
  EXPECT_DOUBLE_EQ(r.cost_history.back(), r.cost);
  for (std::size_t k = 1; k < r.cost_history.size(); ++k) EXPECT_LE(r.cost_history[k], r.cost_history[k - 1]) << k;
  EXPECT_GT(r.iterations, 5);
}

TEST(DenseLevenbergMarquardt, LinearProblemEndsAtTheNormalEquationsSolution) {
  testing::Rng rng(5);
  const int n = 6, rows = 30;
  Eigen::MatrixXd A(rows, n);
  for (int i = 0; i < A.size(); ++i) A.data()[i] = rng.Normal();
  Eigen::VectorXd b(rows);
  for (int i = 0; i < rows; ++i) b[i] = rng.Normal();
  const Eigen::MatrixXd AtA = A.transpose() * A;
  const Eigen::VectorXd Atb = A.transpose() * b;
  auto problem = [&](const Eigen::VectorXd& x, double* F, Eigen::VectorXd* g, Eigen::MatrixXd* H) {
    *F = 0.5 * (A * x - b).squaredNorm();
    if (g != nullptr) *g = AtA * x - Atb;
    if (H != nullptr) *H = AtA;
    return true;
  };
  const DenseLevenbergMarquardtResult r = MinimizeLevenbergMarquardt(problem, Eigen::VectorXd::Zero(n), Tight());
  const Eigen::VectorXd x_star = AtA.ldlt().solve(Atb);
  EXPECT_TRUE(r.converged());
  EXPECT_LT((r.x - x_star).norm(), 1e-9 * x_star.norm());
  EXPECT_NEAR(r.cost, 0.5 * (A * x_star - b).squaredNorm(), 1e-12);
}

TEST(DenseLevenbergMarquardt, RefusesANonFiniteStartAndStopsWhereNothingCanBeComputed) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(MinimizeLevenbergMarquardt(Rosenbrock, Eigen::Vector2d(nan, 0.0), Tight()), std::invalid_argument);
  auto broken = [](const Eigen::VectorXd&, double*, Eigen::VectorXd*, Eigen::MatrixXd*) { return false; };
  const DenseLevenbergMarquardtResult r = MinimizeLevenbergMarquardt(broken, Eigen::Vector2d(1.0, 2.0), Tight());
  EXPECT_EQ(r.reason, StopReason::kNumericalFailure);
  EXPECT_FALSE(r.converged());
}

}  // namespace
}  // namespace inertial
