#include "inertial/signal/log_differentiation.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "test_support.hpp"

namespace inertial {
namespace {

// q_j(t) = a_j t^2 + b_j t + c_j on a jittered grid: Savitzky-Golay of order >= 2 fits it exactly,
// so qd = 2 a t + b and qdd = 2 a up to rounding.
JointSamples Quadratic(int n, std::uint64_t seed) {
  testing::Rng rng(seed);
  JointSamples log;
  log.joint_names = {"a", "b"};
  log.t.resize(n);
  log.q.resize(n, 2);
  log.qd = Eigen::MatrixXd::Constant(n, 2, 99.0);
  log.qdd = Eigen::MatrixXd::Constant(n, 2, 99.0);
  log.tau = Eigen::MatrixXd::Zero(n, 2);
  double t = 0.0;
  for (int i = 0; i < n; ++i) {
    log.t[i] = t;
    log.q(i, 0) = 0.7 * t * t - 0.2 * t + 0.1;
    log.q(i, 1) = -1.3 * t * t + 0.5 * t;
    t += 0.005 * rng.Uniform(0.6, 1.4);
  }
  return log;
}

TEST(LogDifferentiation, DerivesExactlyWhatTheFitRepresents) {
  JointSamples log = Quadratic(200, 4);
  DeriveFromPositions(&log, true, true, SavitzkyGolayOptions{4, 0.1});
  for (int i = 0; i < log.size(); ++i) {
    const double t = log.t[i];
    // Rounding of the scaled Vandermonde QR: a few 1e-12 of values of order 1.
    EXPECT_NEAR(log.qd(i, 0), 1.4 * t - 0.2, 1e-9) << i;
    EXPECT_NEAR(log.qd(i, 1), -2.6 * t + 0.5, 1e-9) << i;
    EXPECT_NEAR(log.qdd(i, 0), 1.4, 1e-7) << i;
    EXPECT_NEAR(log.qdd(i, 1), -2.6, 1e-7) << i;
  }
}

TEST(LogDifferentiation, DerivesOnlyWhatIsAskedFor) {
  JointSamples log = Quadratic(100, 5);
  DeriveFromPositions(&log, false, true, {});
  EXPECT_EQ(log.qd, Eigen::MatrixXd::Constant(100, 2, 99.0));  // measured velocities kept
  EXPECT_NEAR(log.qdd(50, 0), 1.4, 1e-7);
  JointSamples untouched = Quadratic(100, 5);
  DeriveFromPositions(&untouched, false, false, {});
  EXPECT_EQ(untouched.qdd, Eigen::MatrixXd::Constant(100, 2, 99.0));
}

TEST(LogDifferentiation, SaysWhyItCannot) {
  JointSamples few = Quadratic(4, 6);
  try {
    DeriveFromPositions(&few, true, false, SavitzkyGolayOptions{4, 0.1});
    FAIL() << "4 samples fitted by a polynomial of order 4";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()).rfind("cannot derive velocities from q: ", 0), 0u) << e.what();
  }
  JointSamples steep = Quadratic(50, 7);
  steep.q(20, 1) = std::numeric_limits<double>::max();
  steep.q(21, 1) = -std::numeric_limits<double>::max();
  try {
    DeriveFromPositions(&steep, true, true, {});
    FAIL() << "an overflowing derivative was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("not finite at sample"), std::string::npos) << e.what();
  }
}

// Two quadratics recorded with a pause between them (the robot moved on meanwhile): each piece is
// differentiated on its own, so both are exact; one fitted across the pause would not be.
TEST(LogDifferentiation, CutsAtAGapAndSaysSo) {
  JointSamples a = Quadratic(200, 8);  // t in [0, about 1 s]
  const int n1 = a.size();
  JointSamples b = Quadratic(150, 9);
  const double resume = a.t[n1 - 1] + 0.5;  // 0.5 s without samples: about 100 median steps
  JointSamples log = a;
  const int n = n1 + b.size();
  log.t.conservativeResize(n);
  log.q.conservativeResize(n, 2);
  log.qd = log.qdd = Eigen::MatrixXd::Constant(n, 2, 99.0);
  log.tau = Eigen::MatrixXd::Zero(n, 2);
  for (int i = 0; i < b.size(); ++i) {
    const double s = b.t[i];  // the second motion: q = -0.4 s^2 + 0.3 s + 2 in its own time s
    log.t[n1 + i] = resume + s;
    log.q(n1 + i, 0) = -0.4 * s * s + 0.3 * s + 2.0;
    log.q(n1 + i, 1) = 0.9 * s * s - 1.0;
  }
  EXPECT_EQ(GapStarts(log.t, SavitzkyGolayOptions{4, 0.1}), std::vector<int>{n1});
  const LogDerivation d = DeriveFromPositions(&log, true, true, SavitzkyGolayOptions{4, 0.1});
  EXPECT_EQ(d.piece_starts, (std::vector<int>{0, n1}));
  EXPECT_TRUE(d.left_out.empty());
  ASSERT_EQ(d.notices.size(), 2u);
  EXPECT_EQ(d.notices[1].rfind("a gap of 0.5 s after t = ", 0), 0u) << d.notices[1];
  EXPECT_NE(d.notices[1].find("velocities and accelerations are derived in 2 pieces, not across it"), std::string::npos)
      << d.notices[1];
  for (int i = 0; i < n1; ++i) {
    EXPECT_NEAR(log.qd(i, 0), 1.4 * log.t[i] - 0.2, 1e-9) << i;
    EXPECT_NEAR(log.qdd(i, 1), -2.6, 1e-7) << i;
  }
  for (int i = n1; i < n; ++i) {
    const double s = log.t[i] - resume;
    EXPECT_NEAR(log.qd(i, 0), -0.8 * s + 0.3, 1e-8) << i;
    EXPECT_NEAR(log.qdd(i, 1), 1.8, 1e-6) << i;
  }
}

// A few samples alone between two gaps cannot carry a polynomial: they are left out and named.
TEST(LogDifferentiation, LeavesOutAPieceTooShortBetweenGaps) {
  JointSamples log = Quadratic(300, 10);
  for (int i = 100; i < log.size(); ++i) log.t[i] += 0.5;  // a gap after row 99
  for (int i = 103; i < log.size(); ++i) log.t[i] += 0.5;  // and after row 102: rows 100-102 alone
  const JointSamples before = log;
  const LogDerivation d = DeriveFromPositions(&log, true, false, SavitzkyGolayOptions{4, 0.1});
  EXPECT_EQ(d.left_out, (std::vector<int>{100, 101, 102}));
  ASSERT_EQ(log.size(), 297);
  EXPECT_EQ(log.t[100], before.t[103]);
  ASSERT_GE(d.notices.size(), 1u);
  EXPECT_EQ(d.notices[0].rfind("3 samples in 1 piece between gaps (the first from t = ", 0), 0u) << d.notices[0];
  EXPECT_NE(d.notices[0].find("too few for a polynomial of order 4: left out"), std::string::npos) << d.notices[0];
  EXPECT_EQ(d.piece_starts, (std::vector<int>{0, 100}));
}

// Jitter is not a gap: steps of 0.2 to 3.4 times the nominal one (a 100 Hz arm's logging, seen in
// the field), seeded, never cut.
TEST(LogDifferentiation, JitterIsNotAGap) {
  testing::Rng rng(11);
  Eigen::VectorXd t(5000);
  t[0] = 0.0;
  for (int i = 1; i < t.size(); ++i) t[i] = t[i - 1] + 0.01 * (rng.Uniform(0.0, 1.0) < 0.05 ? 3.4 : rng.Uniform(0.2, 1.2));
  EXPECT_TRUE(GapStarts(t, SavitzkyGolayOptions{4, 0.1}).empty());
}

}  // namespace
}  // namespace inertial
