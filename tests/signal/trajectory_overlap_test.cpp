// Whether held-out data retrace the training states: the same log is retraced entirely, a log
// elsewhere in the state space not at all, and a log half of whose samples repeat training states
// by half; a joint that never moves matches; sizes are checked.
#include "inertial/signal/trajectory_overlap.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

namespace inertial {
namespace {

// Two joints on a Lissajous curve q = (sin(a t + phase), sin(b t)), qd its derivative.
JointSamples Curve(int n, double a, double b, double phase, double q_offset = 0.0) {
  JointSamples s;
  s.joint_names = {"j0", "j1"};
  s.t.resize(n);
  s.q.resize(n, 2);
  s.qd.resize(n, 2);
  s.qdd = s.tau = Eigen::MatrixXd::Zero(n, 2);
  for (int i = 0; i < n; ++i) {
    const double t = 0.01 * i;
    s.t[i] = t;
    s.q.row(i) << std::sin(a * t + phase) + q_offset, std::sin(b * t);
    s.qd.row(i) << a * std::cos(a * t + phase), b * std::cos(b * t);
  }
  return s;
}

TEST(TrajectoryOverlap, SameLogIsRetracedOtherPlacesAreNot) {
  const JointSamples train = Curve(2000, 1.0, 1.7, 0.0);
  EXPECT_DOUBLE_EQ(RetracedShare(train, train), 1.0);
  // The same curve 3 rad away in q0 (the ranges cover both logs, so 3 is more than 1 % of them).
  EXPECT_DOUBLE_EQ(RetracedShare(train, Curve(2000, 1.0, 1.7, 0.0, 3.0)), 0.0);
}

TEST(TrajectoryOverlap, HalfRepeatedIsHalf) {
  const JointSamples train = Curve(400, 1.0, 1.7, 0.0);
  JointSamples other = Curve(400, 1.0, 1.7, 0.0);
  const JointSamples away = Curve(400, 1.0, 1.7, 0.0, 5.0);
  // Every odd sample moved away: 200 of the 400 (all checked, fewer than 500) are retraced.
  for (int i = 1; i < 400; i += 2) {
    other.q.row(i) = away.q.row(i);
    other.qd.row(i) = away.qd.row(i);
  }
  EXPECT_DOUBLE_EQ(RetracedShare(train, other), 0.5);
  // A tolerance that spans the whole range matches everything.
  EXPECT_DOUBLE_EQ(RetracedShare(train, other, 1.0), 1.0);
}

TEST(TrajectoryOverlap, AJointThatNeverMovesMatchesAndSizesAreChecked) {
  JointSamples train = Curve(300, 1.0, 1.7, 0.0), other = train;
  train.q.col(1).setConstant(0.25);
  train.qd.col(1).setZero();
  other.q.col(1).setConstant(0.25);
  other.qd.col(1).setZero();
  EXPECT_DOUBLE_EQ(RetracedShare(train, other), 1.0);
  EXPECT_THROW(RetracedShare(JointSamples{}, other), std::invalid_argument);
  JointSamples one_joint = other;
  one_joint.q = other.q.leftCols(1);
  one_joint.qd = other.qd.leftCols(1);
  EXPECT_THROW(RetracedShare(train, one_joint), std::invalid_argument);
}

}  // namespace
}  // namespace inertial
