// The Fourier excitation: closed-form derivatives against central differences, the amplitude
// bound, periodicity and the seeded factory; one harmonic in closed form.
#include "inertial/model/fourier_trajectory.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace inertial {
namespace {

constexpr double kPi = 3.14159265358979323846;

// The Fourier trajectory's closed-form derivatives match central differences; the amplitude
// bound holds, the series is periodic, and the random factory is deterministic for a seed.
TEST(FourierTrajectory, DerivativesBoundPeriodAndSeed) {
  const double amplitude = 0.8;
  FourierTrajectory traj = RandomFourierTrajectory(4, 5, 0.25, amplitude, 7);
  traj.q0 = Eigen::Vector4d(0.1, -0.2, 0.3, 1.0);
  ASSERT_EQ(traj.num_joints(), 4);
  ASSERT_EQ(traj.num_harmonics(), 5);
  EXPECT_LT((traj.AmplitudeBound() - Eigen::VectorXd::Constant(4, amplitude)).cwiseAbs().maxCoeff(), 1e-12);
  const double dt = 1e-5;
  double max_dev = 0.0;
  for (int i = 0; i <= 4000; ++i) {
    const double t = i * traj.period() / 4000;
    const JointTrajectoryPoint p = traj.Evaluate(t), plus = traj.Evaluate(t + dt), minus = traj.Evaluate(t - dt);
    EXPECT_LT(((plus.q - minus.q) / (2 * dt) - p.qd).cwiseAbs().maxCoeff(), 1e-7);
    EXPECT_LT(((plus.qd - minus.qd) / (2 * dt) - p.qdd).cwiseAbs().maxCoeff(), 1e-6);
    max_dev = std::max(max_dev, (p.q - traj.q0).cwiseAbs().maxCoeff());
    const JointTrajectoryPoint later = traj.Evaluate(t + 3 * traj.period());
    EXPECT_LT((later.q - p.q).cwiseAbs().maxCoeff(), 1e-10);
    EXPECT_LT((later.qdd - p.qdd).cwiseAbs().maxCoeff(), 1e-9);
  }
  EXPECT_LE(max_dev, amplitude);
  EXPECT_GT(max_dev, 0.3 * amplitude);  // the bound is not vacuous

  const FourierTrajectory again = RandomFourierTrajectory(4, 5, 0.25, amplitude, 7);
  const FourierTrajectory other = RandomFourierTrajectory(4, 5, 0.25, amplitude, 8);
  EXPECT_EQ(again.a, RandomFourierTrajectory(4, 5, 0.25, amplitude, 7).a);
  EXPECT_EQ(again.b, traj.b);
  EXPECT_GT((other.a - again.a).cwiseAbs().maxCoeff(), 1e-3);
}

// A single harmonic in closed form: q = q0 + a/w sin(w t) - b/w cos(w t).
TEST(FourierTrajectory, SingleHarmonicClosedForm) {
  FourierTrajectory traj;
  traj.base_frequency_hz = 0.5;
  traj.q0 = Eigen::VectorXd::Constant(1, 0.3);
  traj.a = Eigen::MatrixXd::Constant(1, 1, 2.0);
  traj.b = Eigen::MatrixXd::Constant(1, 1, -1.0);
  const double w = kPi, t = 0.37;
  const JointTrajectoryPoint p = traj.Evaluate(t);
  EXPECT_NEAR(p.q[0], 0.3 + 2.0 / w * std::sin(w * t) + 1.0 / w * std::cos(w * t), 1e-15);
  EXPECT_NEAR(p.qd[0], 2.0 * std::cos(w * t) - std::sin(w * t), 1e-15);
  EXPECT_NEAR(p.qdd[0], -2.0 * w * std::sin(w * t) - w * std::cos(w * t), 1e-14);
  EXPECT_NEAR(traj.AmplitudeBound()[0], std::sqrt(5.0) / w, 1e-15);
}

TEST(FourierTrajectory, RefusesBadInput) {
  FourierTrajectory traj = RandomFourierTrajectory(2, 3, 0.2, 0.5, 1);
  traj.b.resize(2, 2);
  EXPECT_THROW(traj.Evaluate(0.0), std::invalid_argument);
  traj = RandomFourierTrajectory(2, 3, 0.2, 0.5, 1);
  EXPECT_THROW(traj.Evaluate(std::nan("")), std::invalid_argument);
  traj.base_frequency_hz = 0.0;
  EXPECT_THROW(traj.AmplitudeBound(), std::invalid_argument);
  EXPECT_THROW(RandomFourierTrajectory(0, 3, 0.2, 0.5, 1), std::invalid_argument);
  EXPECT_THROW(RandomFourierTrajectory(2, 3, 0.2, -0.5, 1), std::invalid_argument);
}

}  // namespace
}  // namespace inertial
