#include "inertial/estimation/batch/levenberg_marquardt.hpp"

#include <gtest/gtest.h>

#include <memory>

#include "estimation/synthetic_regression.hpp"
#include "inertial/estimation/batch/linear_least_squares.hpp"
#include "inertial/inertia/closed_form_bodies.hpp"
#include "inertial/inertia/consistency.hpp"
#include "inertial/inertia/eigenvalue_parameterization.hpp"
#include "inertial/inertia/exponential_parameterization.hpp"
#include "inertial/inertia/linear_parameterization.hpp"
#include "inertial/inertia/log_cholesky.hpp"
#include "inertial/model/rigid_body_regressor.hpp"
#include "test_support.hpp"

namespace inertial {
namespace {

using testing::RelativeError;
using testing::Rng;
using testing::SyntheticRegression;

Vector10 IdentityInertia() {
  Vector10 pi;
  pi << 1, 0, 0, 0, 1, 1, 1, 0, 0, 0;
  return pi;
}

std::vector<std::unique_ptr<Parameterization>> AllParameterizations() {
  std::vector<std::unique_ptr<Parameterization>> all;
  all.push_back(std::make_unique<LinearParameterization>());
  all.push_back(std::make_unique<EigenvalueParameterization>());
  all.push_back(std::make_unique<ExponentialParameterization>());
  all.push_back(std::make_unique<LogCholeskyParameterization>());
  return all;
}

// Every parameterization, started from the identity inertia, reaches the exact body on noise-free
// data, and the linear-least-squares optimum on noisy data whose optimum is consistent.
TEST(LevenbergMarquardt, EveryParameterizationFindsTheConsistentOptimum) {
  Rng rng(2);
  const auto all = AllParameterizations();
  for (int trial = 0; trial < 20; ++trial) {
    // One draw per statement, in the order the x86-64 build drew them (see testing::Rng).
    const Pose pose{rng.Rotation(), rng.UniformVector<3>(-0.3, 0.3)};
    const Vector3 L = rng.UniformVector<3>(0.05, 0.5);
    const double mass = rng.Uniform(0.2, 2.0);
    const InertialParams body = BodyFromSecondMoments(mass, L, pose);
    for (double noise : {0.0, 0.01}) {
      const LinearRegression reg = SyntheticRegression(rng, body, 40, noise);
      const LinearLeastSquaresResult lls = SolveLinearLeastSquares(reg);
      ASSERT_TRUE(IsPhysicallyConsistent(InertialParams::FromVector(lls.pi)));
      for (const auto& p : all) {
        Vector10 x0;
        ASSERT_TRUE(p->FromPi(IdentityInertia(), &x0)) << p->name();
        LevenbergMarquardtOptions options;
        options.function_tolerance = options.step_tolerance = 1e-12;
        options.gradient_tolerance = 1e-12;
        // The eigenvalue map (rotation and principal moments) is the slowest near bodies with two
        // nearly equal principal moments, where its rotation is nearly undetermined (the paper's
        // Section VI finds it the slowest too): 200 iterations sufficed for the GCC build, one
        // trial needed more under clang's rounding. The cap guards against a loop, not a rate.
        options.max_iterations = 1000;
        const LevenbergMarquardtResult fit = FitLevenbergMarquardt(*p, reg, x0, options);
        EXPECT_TRUE(fit.converged()) << p->name() << " " << ToString(fit.reason) << " after " << fit.iterations;
        if (p->name() != "eigenvalue") {
          EXPECT_LE(fit.iterations, 200) << p->name();
        }
        EXPECT_LT(RelativeError(fit.pi, lls.pi), 1e-6) << p->name() << " noise " << noise;
        EXPECT_LE(fit.cost, fit.initial_cost);
        EXPECT_GE(fit.cost, lls.cost * (1 - 1e-12) - 1e-18);  // nobody beats the global optimum
      }
    }
  }
}

// When the unconstrained optimum is nonphysical, the consistent parameterizations still return a
// consistent body, with a cost no lower than the linear optimum's.
TEST(LevenbergMarquardt, ConsistentMapsStayConsistentWhenTheLinearOptimumIsNot) {
  Rng rng(3);
  // A thin plate (Lz small) with heavy noise: the linear estimate breaks the triangle inequality.
  const InertialParams plate = BodyFromSecondMoments(1.0, Vector3(0.1, 0.1, 1e-4), Pose{rng.Rotation(), Vector3::Zero()});
  int nonphysical_cases = 0;
  for (int trial = 0; trial < 30; ++trial) {
    const LinearRegression reg = SyntheticRegression(rng, plate, 10, 0.2);
    const LinearLeastSquaresResult lls = SolveLinearLeastSquares(reg);
    if (IsPhysicallyConsistent(InertialParams::FromVector(lls.pi))) continue;
    ++nonphysical_cases;
    const LogCholeskyParameterization lc;
    Vector10 x0;
    ASSERT_TRUE(lc.FromPi(IdentityInertia(), &x0));
    const LevenbergMarquardtResult fit = FitLevenbergMarquardt(lc, reg, x0);
    EXPECT_TRUE(fit.x.allFinite());
    EXPECT_TRUE(lc.YieldsConsistentBody(fit.x));
    EXPECT_GT(InertialParams::FromVector(fit.pi).mass(), 0.0);
    EXPECT_GE(fit.cost, lls.cost);
  }
  EXPECT_GT(nonphysical_cases, 5);
}

TEST(LevenbergMarquardt, ReportsWhyItStopped) {
  Rng rng(4);
  const LinearRegression reg = SyntheticRegression(rng, SolidSphere(1.0, 0.3), 20, 0.05);
  const LogCholeskyParameterization lc;
  Vector10 x0;
  ASSERT_TRUE(lc.FromPi(IdentityInertia(), &x0));
  LevenbergMarquardtOptions one;
  one.max_iterations = 1;
  const LevenbergMarquardtResult capped = FitLevenbergMarquardt(lc, reg, x0, one);
  EXPECT_EQ(capped.reason, StopReason::kMaxIterations);
  EXPECT_EQ(capped.iterations, 1);
  EXPECT_FALSE(capped.converged());
  const LevenbergMarquardtResult full = FitLevenbergMarquardt(lc, reg, x0);
  EXPECT_TRUE(full.converged()) << ToString(full.reason);
  EXPECT_LE(full.iterations, 50);
  EXPECT_EQ(ToString(StopReason::kGradient), "gradient");
  Vector10 bad = x0;
  bad[0] = std::nan("");
  EXPECT_THROW(FitLevenbergMarquardt(lc, reg, bad), std::invalid_argument);
}

}  // namespace
}  // namespace inertial
