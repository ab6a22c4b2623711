// Choosing rows of a joint log (sample_selection.hpp), by hand: the rows kept, the log of those
// rows, and the held-out split by time on a uniform, a jittered and a paused log.
#include "inertial/signal/sample_selection.hpp"

#include <gtest/gtest.h>

#include <stdexcept>

namespace inertial {
namespace {

JointSamples Ramp(const Eigen::VectorXd& t) {
  JointSamples d;
  d.joint_names = {"j"};
  d.t = t;
  d.q = t;
  d.qd = 2.0 * t;
  d.qdd = 3.0 * t;
  d.tau = 4.0 * t;
  return d;
}

TEST(SampleSelection, RowsByHand) {
  EXPECT_EQ(RowsExcept(6, {1, 4}), (std::vector<int>{0, 2, 3, 5}));
  EXPECT_EQ(RowsExcept(3, {}), (std::vector<int>{0, 1, 2}));
  EXPECT_EQ(RowRange(2, 9, 3), (std::vector<int>{2, 5, 8}));
  const JointSamples d = Ramp(Eigen::VectorXd::LinSpaced(5, 0.0, 4.0));
  const JointSamples s = SelectSamples(d, {1, 3});
  ASSERT_EQ(s.size(), 2);
  EXPECT_EQ(s.t[1], 3.0);
  EXPECT_EQ(s.tau(0, 0), 4.0);
  EXPECT_EQ(s.joint_names, d.joint_names);
  EXPECT_THROW(SelectSamples(d, {5}), std::invalid_argument);
}

TEST(SampleSelection, HoldoutStartFollowsTheTimeStamps) {
  // Uniform: 0..9 s, the last 30 % of the time is t >= 6.3 s: rows 7, 8, 9.
  EXPECT_EQ(HoldoutStart(Eigen::VectorXd::LinSpaced(10, 0.0, 9.0), 0.3), 7);
  // Jittered: 100 samples at 0.1 s over [0, 10) s, then 400 at 0.01 s over [10, 14) s. By count the
  // last 30 % would start at row 350 (t = 12.5 s); by time at t >= 13.99 - 0.3 * 13.99 s.
  Eigen::VectorXd t(500);
  for (int i = 0; i < 100; ++i) t[i] = 0.1 * i;
  for (int i = 0; i < 400; ++i) t[100 + i] = 10.0 + 0.01 * i;
  const int start = HoldoutStart(t, 0.3);
  const double cut = t[499] - 0.3 * (t[499] - t[0]);
  EXPECT_GE(t[start], cut);
  EXPECT_LT(t[start - 1], cut);
  EXPECT_EQ(start, 98);  // cut = 0.7 * 13.99 = 9.793 s: among the slow samples, at t = 9.8 s
  // A pause counts as time: 0..4 s, then 10..14 s at 1 s steps; the last half of the time is t >= 7.
  Eigen::VectorXd paused(10);
  paused << 0, 1, 2, 3, 4, 10, 11, 12, 13, 14;
  EXPECT_EQ(HoldoutStart(paused, 0.5), 5);
  EXPECT_THROW(HoldoutStart(Eigen::VectorXd::LinSpaced(10, 0.0, 9.0), 0.0), std::invalid_argument);
  EXPECT_THROW(HoldoutStart(Eigen::VectorXd::LinSpaced(10, 0.0, 9.0), 1.0), std::invalid_argument);
  EXPECT_THROW(HoldoutStart(Eigen::VectorXd::LinSpaced(10, 0.0, 9.0), 0.1), std::invalid_argument);  // 1 held out
  EXPECT_THROW(HoldoutStart(Eigen::VectorXd::LinSpaced(10, 0.0, 9.0), 0.9), std::invalid_argument);  // 1 to train
}

}  // namespace
}  // namespace inertial
