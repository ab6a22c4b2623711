// Several runs laid end to end (recorded_runs.hpp), by hand: the rows and times of each run, the
// shift that separates them, and the held-out split taken run by run.
#include "inertial/signal/recorded_runs.hpp"

#include <gtest/gtest.h>

#include <stdexcept>

namespace inertial {
namespace {

// n samples every `step` s from t0; q = t, tau = 10 t + k (k tells the runs apart).
JointSamples RampRun(int n, double t0, double step, double k) {
  JointSamples d;
  d.joint_names = {"a", "b"};
  d.t = Eigen::VectorXd::LinSpaced(n, t0, t0 + step * (n - 1));
  d.q = d.qd = d.qdd = Eigen::MatrixXd::Zero(n, 2);
  d.q.col(0) = d.t;
  d.tau = Eigen::MatrixXd::Constant(n, 2, k);
  d.tau.col(0) += 10.0 * d.t;
  return d;
}

TEST(RecordedRuns, LaidEndToEndWithAClearGap) {
  // Both runs start at t = 0 on their own clocks; the second at 0.2 s steps (10 steps = 2 s > 1 s).
  const RecordedRuns r = JoinRuns({"a.csv", "b.csv"}, {RampRun(11, 0.0, 0.01, 1.0), RampRun(6, 0.0, 0.2, 2.0)});
  EXPECT_EQ(r.num_runs(), 2);
  EXPECT_EQ(r.starts, (std::vector<int>{0, 11, 17}));
  ASSERT_EQ(r.shifts.size(), 2u);
  EXPECT_EQ(r.shifts[0], 0.0);
  EXPECT_DOUBLE_EQ(r.shifts[1], 0.1 + 1.0);  // the first ends at 0.1 s; separation max(1, 10 * 0.01)
  EXPECT_DOUBLE_EQ(r.samples.t[11], 1.1);
  EXPECT_EQ(r.samples.tau(11, 1), 2.0);
  const JointSamples b = r.Run(1);
  ASSERT_EQ(b.size(), 6);
  EXPECT_DOUBLE_EQ(b.t[5] - r.shifts[1], 1.0);  // its own clock
  EXPECT_EQ(b.q(5, 0), 1.0);
  // The other way round: after the slow run, 10 of its steps (2 s) separate them.
  const RecordedRuns s = JoinRuns({"b.csv", "a.csv"}, {RampRun(6, 0.0, 0.2, 2.0), RampRun(11, 0.0, 0.01, 1.0)});
  EXPECT_DOUBLE_EQ(s.shifts[1], 1.0 + 2.0);
  EXPECT_THROW(JoinRuns({}, {}), std::invalid_argument);
  JointSamples other = RampRun(3, 0.0, 0.1, 0.0);
  other.joint_names = {"a", "c"};
  try {
    JoinRuns({"a.csv", "c.csv"}, {RampRun(3, 0.0, 0.1, 0.0), other});
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()), "c.csv: its joints differ from those of a.csv");
  }
}

TEST(RecordedRuns, HeldOutRunByRun) {
  const RecordedRuns r = JoinRuns({"a.csv", "b.csv"}, {RampRun(10, 0.0, 1.0, 1.0), RampRun(20, 0.0, 1.0, 2.0)});
  RecordedRuns train, held;
  SplitRunsHoldout(r, 0.3, &train, &held);
  // a: 0..9 s, held t >= 6.3: 3 rows; b: 0..19 s, held t >= 13.3: 6 rows.
  EXPECT_EQ(train.starts, (std::vector<int>{0, 7, 21}));
  EXPECT_EQ(held.starts, (std::vector<int>{0, 3, 9}));
  EXPECT_EQ(held.Run(1).tau(0, 1), 2.0);
  EXPECT_DOUBLE_EQ(held.Run(1).t[0] - held.shifts[1], 14.0);
  EXPECT_EQ(train.names, r.names);
  try {
    SplitRunsHoldout(JoinRuns({"a.csv", "tiny.csv"}, {RampRun(10, 0.0, 1.0, 1.0), RampRun(3, 0.0, 1.0, 2.0)}), 0.3, &train, &held);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()).rfind("tiny.csv: holdout: 3 samples cannot be split", 0), 0u) << e.what();
  }
}

}  // namespace
}  // namespace inertial
