// What every recursive estimator shares (RecursiveEstimator, tested through the linear RLS, the
// simplest of them): the order of the checks on a sample (size, then finiteness, then time), which
// samples advance the clock, the counters, and a state restored only when it can be trusted,
// leaving the estimator untouched otherwise.
#include "inertial/estimation/online/recursive_estimator.hpp"

#include <gtest/gtest.h>

#include <limits>

#include "inertial/estimation/online/linear_rls.hpp"

namespace inertial {
namespace {

TEST(OnlineBodyEstimator, WrongSizesAreRejectedWithoutThrowing) {
  LinearRls rls(6, Eigen::VectorXd::Zero(10), Eigen::VectorXd::Ones(10));
  EXPECT_EQ(rls.Update(0.0, Eigen::MatrixXd::Zero(5, 10), Eigen::VectorXd::Zero(6)), UpdateStatus::kWrongSize);
  EXPECT_EQ(rls.Update(0.0, Eigen::MatrixXd::Zero(6, 10), Eigen::VectorXd::Zero(7)), UpdateStatus::kWrongSize);
  EXPECT_EQ(rls.counters().rejected(), 2u);
  EXPECT_EQ(rls.parameters(), Eigen::VectorXd::Zero(10));
}

// Two coefficients measured together, y = a w0 + b w1, sigma 1, a 30-sigma gate.
LinearRls TwoCoefficients() { return LinearRls(1, Eigen::Vector2d(0.0, 0.0), Eigen::Vector2d(1.0, 1.0)); }

TEST(RecursiveEstimator, ChecksSizeThenFinitenessThenTime) {
  LinearRls rls = TwoCoefficients();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const Eigen::MatrixXd A = Eigen::RowVector2d(1.0, 0.5);
  const Eigen::VectorXd y = Eigen::VectorXd::Constant(1, 0.3);
  EXPECT_FALSE(rls.has_time());
  // A wrong size wins over a NaN time; a NaN wins over an order that cannot be judged yet.
  EXPECT_EQ(rls.Update(nan, Eigen::MatrixXd::Zero(2, 2), y), UpdateStatus::kWrongSize);
  EXPECT_EQ(rls.Update(nan, A, y), UpdateStatus::kNonFinite);
  Eigen::MatrixXd A_inf = A;
  A_inf(0, 1) = std::numeric_limits<double>::infinity();
  EXPECT_EQ(rls.Update(1.0, A_inf, y), UpdateStatus::kNonFinite);
  EXPECT_FALSE(rls.has_time());  // no rejected sample set the clock
  ASSERT_EQ(rls.Update(1.0, A, y), UpdateStatus::kAccepted);
  EXPECT_TRUE(rls.has_time());
  EXPECT_EQ(rls.last_time(), 1.0);
  EXPECT_EQ(rls.Update(1.0, A, y), UpdateStatus::kOutOfOrder);  // the same time again
  EXPECT_EQ(rls.Update(0.5, A, y), UpdateStatus::kOutOfOrder);
  // An outlier (1000 sigma) is refused but was a valid sample in time: the clock moves on.
  EXPECT_EQ(rls.Update(2.0, A, Eigen::VectorXd::Constant(1, 1000.0)), UpdateStatus::kOutlier);
  EXPECT_EQ(rls.last_time(), 2.0);
  EXPECT_EQ(rls.Update(1.5, A, y), UpdateStatus::kOutOfOrder);
  const UpdateCounters& c = rls.counters();
  EXPECT_EQ(c.accepted(), 1u);
  EXPECT_EQ(c[UpdateStatus::kWrongSize], 1u);
  EXPECT_EQ(c[UpdateStatus::kNonFinite], 2u);
  EXPECT_EQ(c[UpdateStatus::kOutOfOrder], 3u);
  EXPECT_EQ(c[UpdateStatus::kOutlier], 1u);
  EXPECT_EQ(c.rejected(), 7u);
  // CountSample counts what a caller rejected before the estimator saw it.
  rls.CountSample(UpdateStatus::kBuffered);
  EXPECT_EQ(rls.counters()[UpdateStatus::kBuffered], 1u);
  EXPECT_EQ(rls.counters().rejected(), 7u);
}

TEST(RecursiveEstimator, StateRoundTripsAndUntrustworthyStatesChangeNothing) {
  LinearRls a = TwoCoefficients();
  ASSERT_EQ(a.Update(1.0, Eigen::RowVector2d(1.0, 0.5), Eigen::VectorXd::Constant(1, 0.3)), UpdateStatus::kAccepted);
  ASSERT_EQ(a.Update(2.0, Eigen::RowVector2d(-0.2, 1.0), Eigen::VectorXd::Constant(1, -0.4)), UpdateStatus::kAccepted);
  const EstimatorState saved = a.State();
  EXPECT_EQ(saved.kind, "linear_rls");
  EXPECT_EQ(saved.x, a.parameters());
  EXPECT_EQ(saved.P, a.Covariance());
  EXPECT_TRUE(saved.has_time);
  EXPECT_EQ(saved.last_time, 2.0);
  EXPECT_EQ(saved.counters.accepted(), 2u);

  LinearRls b = TwoCoefficients();
  const EstimatorState fresh = b.State();
  auto expect_unchanged = [&](const char* what) {
    EXPECT_EQ(b.parameters(), fresh.x) << what;
    EXPECT_EQ(b.Covariance(), fresh.P) << what;
    EXPECT_FALSE(b.has_time()) << what;
    EXPECT_EQ(b.counters().accepted(), 0u) << what;
  };
  std::string why;
  EstimatorState bad = saved;
  bad.kind = "gradient";
  EXPECT_FALSE(b.Restore(bad, &why));
  EXPECT_NE(why.find("'gradient'"), std::string::npos) << why;
  expect_unchanged("kind");
  bad = saved;
  bad.x = Eigen::Vector3d::Zero();
  EXPECT_FALSE(b.Restore(bad, &why));
  EXPECT_NE(why.find("3 parameters"), std::string::npos) << why;
  expect_unchanged("size");
  bad = saved;
  bad.x[1] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(b.Restore(bad, &why));
  expect_unchanged("NaN");
  bad = saved;
  bad.last_time = 2 * kMaxStateTime;
  EXPECT_FALSE(b.Restore(bad, &why));
  expect_unchanged("time");
  bad = saved;
  bad.P(0, 1) += 0.1;  // not symmetric
  EXPECT_FALSE(b.Restore(bad, &why));
  EXPECT_NE(why.find("symmetric"), std::string::npos) << why;
  expect_unchanged("asymmetric");
  bad = saved;
  bad.P = Eigen::Matrix2d(Eigen::Vector2d(1.0, -1.0).asDiagonal());  // indefinite
  EXPECT_FALSE(b.Restore(bad, &why));
  EXPECT_NE(why.find("positive definite"), std::string::npos) << why;
  expect_unchanged("indefinite");
  bad = saved;
  bad.x[0] = 10 * kMaxStateCoefficient;  // a coefficient beyond any physical scale
  EXPECT_FALSE(b.Restore(bad, &why));
  expect_unchanged("huge");

  ASSERT_TRUE(b.Restore(saved, &why)) << why;
  EXPECT_EQ(b.parameters(), a.parameters());
  EXPECT_EQ(b.Covariance(), a.Covariance());
  EXPECT_EQ(b.last_time(), 2.0);
  EXPECT_EQ(b.counters().accepted(), 2u);
  // Both continue bit for bit.
  const Eigen::MatrixXd A = Eigen::RowVector2d(0.7, 0.7);
  const Eigen::VectorXd y = Eigen::VectorXd::Constant(1, 0.1);
  EXPECT_EQ(b.Update(2.0, A, y), UpdateStatus::kOutOfOrder);
  ASSERT_EQ(a.Update(3.0, A, y), UpdateStatus::kAccepted);
  ASSERT_EQ(b.Update(3.0, A, y), UpdateStatus::kAccepted);
  EXPECT_EQ(a.parameters(), b.parameters());
}

}  // namespace
}  // namespace inertial
