// FitExcitationToLimits and FirstLimitViolation against closed-form single-harmonic trajectories:
// q = q0 + (a sin(w t) - b cos(w t)) / w, qd = a cos(w t) + b sin(w t), whose largest excursion
// sqrt(a^2 + b^2) / w and speed sqrt(a^2 + b^2) are reached on a grid holding the quarter periods.
#include "inertial/model/joint_limits.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>

namespace inertial {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kPi = 3.14159265358979323846;

// Two joints, one harmonic at f Hz, a = (1, 2), b = 0: excursions 1/w and 2/w, speeds 1 and 2.
FourierTrajectory TwoJoints(double f) {
  FourierTrajectory traj;
  traj.base_frequency_hz = f;
  traj.q0 = Eigen::Vector2d::Zero();
  traj.a = Eigen::Vector2d(1.0, 2.0);
  traj.b = Eigen::Vector2d::Zero();
  return traj;
}

// One period sampled at 1/(8 f): holds t = 0 (top speed) and a quarter period (largest excursion).
Eigen::VectorXd Grid(double f) { return Eigen::VectorXd::LinSpaced(9, 0.0, 1.0 / f); }

TEST(JointLimits, CentresInTheRangeAndLeavesAWideRangeAlone) {
  const double f = 0.5, w = 2 * kPi * f;  // excursions 0.318 and 0.637 rad
  FourierTrajectory traj = TwoJoints(f);
  const std::vector<JointLimits> limits{{0.3, 2.7, kInf, kInf}, {-3.5, 1.5, kInf, kInf}};
  const std::vector<LimitedExcitation> limited = FitExcitationToLimits(limits, Grid(f), 0.05, &traj);
  EXPECT_TRUE(limited.empty());
  EXPECT_DOUBLE_EQ(traj.q0[0], 1.5);
  EXPECT_DOUBLE_EQ(traj.q0[1], -1.0);
  EXPECT_DOUBLE_EQ(traj.a(1, 0), 2.0);  // unscaled
  EXPECT_NEAR(traj.AmplitudeBound()[1], 2.0 / w, 1e-15);
}

TEST(JointLimits, ScalesAJointToItsPositionRangeLessTheMargin) {
  const double f = 0.5, w = 2 * kPi * f;
  FourierTrajectory traj = TwoJoints(f);
  // Joint 1 may move 0.2 rad either way of 0.1; with a 5 % margin its excursion becomes 0.19.
  const std::vector<JointLimits> limits{{-kInf, kInf, kInf, kInf}, {-0.1, 0.3, kInf, kInf}};
  const std::vector<LimitedExcitation> limited = FitExcitationToLimits(limits, Grid(f), 0.05, &traj);
  ASSERT_EQ(limited.size(), 1u);
  EXPECT_EQ(limited[0].joint, 1);
  EXPECT_EQ(limited[0].kind, LimitKind::kPosition);
  EXPECT_NEAR(limited[0].scale, 0.19 / (2.0 / w), 1e-12);
  EXPECT_DOUBLE_EQ(traj.q0[1], 0.1);
  EXPECT_NEAR(traj.AmplitudeBound()[1], 0.19, 1e-12);
  EXPECT_DOUBLE_EQ(traj.q0[0], 0.0);   // no range: untouched
  EXPECT_DOUBLE_EQ(traj.a(0, 0), 1.0);
}

TEST(JointLimits, ScalesAJointBelowItsVelocityLimit) {
  const double f = 0.5;
  FourierTrajectory traj = TwoJoints(f);
  const std::vector<JointLimits> limits{{-kInf, kInf, 1.5, kInf}, {-kInf, kInf, 1.0, kInf}};
  const std::vector<LimitedExcitation> limited = FitExcitationToLimits(limits, Grid(f), 0.1, &traj);
  ASSERT_EQ(limited.size(), 1u);  // joint 0 tops at 1 rad/s < 0.9 * 1.5
  EXPECT_EQ(limited[0].joint, 1);
  EXPECT_EQ(limited[0].kind, LimitKind::kVelocity);
  EXPECT_NEAR(limited[0].scale, 0.9 / 2.0, 1e-12);
  EXPECT_NEAR(traj.Evaluate(0.0).qd[1], 0.9, 1e-12);  // qd(0) = a: the top speed
}

TEST(JointLimits, MovesTheCentreInsideAOneSidedRange) {
  const double f = 0.5, w = 2 * kPi * f;
  FourierTrajectory traj = TwoJoints(f);
  const std::vector<JointLimits> limits{{0.2, kInf, kInf, kInf}, {-kInf, -0.5, kInf, kInf}};
  EXPECT_TRUE(FitExcitationToLimits(limits, Grid(f), 0.05, &traj).empty());
  EXPECT_NEAR(traj.q0[0], 0.2 + 1.05 / w, 1e-12);
  EXPECT_NEAR(traj.q0[1], -0.5 - 1.05 * 2.0 / w, 1e-12);
  // A one-sided range that already holds the excursion about 0 keeps q0 = 0.
  FourierTrajectory wide = TwoJoints(f);
  EXPECT_TRUE(FitExcitationToLimits({{-5.0, kInf, kInf, kInf}, {-kInf, 5.0, kInf, kInf}}, Grid(f), 0.05, &wide).empty());
  EXPECT_DOUBLE_EQ(wide.q0[0], 0.0);
  EXPECT_DOUBLE_EQ(wide.q0[1], 0.0);
}

TEST(JointLimits, FittedExcitationStaysInsideOnAFineGrid) {
  // A random 5-harmonic excitation: between the grid points of the fit it stays inside too (the
  // margin is far larger than what the grid misses at 100 samples per period of the top harmonic).
  FourierTrajectory traj = RandomFourierTrajectory(3, 5, 0.1, 0.9, 7);
  const std::vector<JointLimits> limits{{-0.8, 0.8, 20, kInf}, {0.3, 2.7, 0.5, kInf}, {-3.5, 1.5, 15, kInf}};
  FitExcitationToLimits(limits, Eigen::VectorXd::LinSpaced(2001, 0.0, 10.0), 0.05, &traj);
  for (int i = 0; i <= 20000; ++i) {
    const JointTrajectoryPoint p = traj.Evaluate(i * 5e-4);
    for (int j = 0; j < 3; ++j) {
      EXPECT_GE(p.q[j], limits[j].lower);
      EXPECT_LE(p.q[j], limits[j].upper);
      EXPECT_LE(std::abs(p.qd[j]), limits[j].velocity);
    }
  }
}

TEST(JointLimits, FirstViolationInTimeThenJointOrder) {
  JointSamples s;
  s.t = Eigen::Vector3d(0.0, 0.1, 0.2);
  s.q = Eigen::MatrixXd::Zero(3, 2);
  s.qd = Eigen::MatrixXd::Zero(3, 2);
  s.tau = Eigen::MatrixXd::Zero(3, 2);
  const std::vector<JointLimits> limits{{-1, 1, 2, 10}, {-1, 1, 2, 10}};
  EXPECT_FALSE(FirstLimitViolation(s, limits).has_value());
  s.q(2, 0) = 1.5;     // later
  s.tau(1, 1) = -11;   // first in time
  s.qd(1, 1) = 2.5;    // same sample and joint: velocity comes before effort
  const std::optional<LimitViolation> v = FirstLimitViolation(s, limits);
  ASSERT_TRUE(v.has_value());
  EXPECT_EQ(v->joint, 1);
  EXPECT_EQ(v->kind, LimitKind::kVelocity);
  EXPECT_DOUBLE_EQ(v->time, 0.1);
  EXPECT_DOUBLE_EQ(v->value, 2.5);
  EXPECT_DOUBLE_EQ(v->limit, 2.0);
  s.qd(1, 1) = 0.0;
  EXPECT_EQ(FirstLimitViolation(s, limits)->kind, LimitKind::kEffort);
  s.tau(1, 1) = 0.0;
  const std::optional<LimitViolation> p = FirstLimitViolation(s, limits);
  EXPECT_EQ(p->kind, LimitKind::kPosition);
  EXPECT_DOUBLE_EQ(p->limit, 1.0);
  EXPECT_STREQ(ToString(p->kind), "position");
}

TEST(JointLimits, RefusesBadLimitsAndSizes) {
  FourierTrajectory traj = TwoJoints(0.5);
  const Eigen::VectorXd t = Grid(0.5);
  EXPECT_THROW(FitExcitationToLimits({JointLimits{}}, t, 0.05, &traj), std::invalid_argument);
  EXPECT_THROW(FitExcitationToLimits({{1, 0, kInf, kInf}, {}}, t, 0.05, &traj), std::invalid_argument);
  EXPECT_THROW(FitExcitationToLimits({{std::nan(""), 0, kInf, kInf}, {}}, t, 0.05, &traj), std::invalid_argument);
  EXPECT_THROW(FitExcitationToLimits({{-1, 1, 0, kInf}, {}}, t, 0.05, &traj), std::invalid_argument);
  EXPECT_THROW(FitExcitationToLimits({{}, {}}, t, 1.0, &traj), std::invalid_argument);
  EXPECT_THROW(FitExcitationToLimits({{}, {}}, Eigen::VectorXd(), 0.05, &traj), std::invalid_argument);
  JointSamples s;
  s.t = Eigen::VectorXd::Zero(1);
  s.q = s.qd = s.tau = Eigen::MatrixXd::Zero(1, 2);
  EXPECT_THROW(FirstLimitViolation(s, {JointLimits{}}), std::invalid_argument);
}

}  // namespace
}  // namespace inertial
