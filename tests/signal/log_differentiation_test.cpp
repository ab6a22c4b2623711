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

}  // namespace
}  // namespace inertial
