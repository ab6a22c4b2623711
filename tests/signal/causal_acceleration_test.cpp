// The causal acceleration filter: the first sample only primes it; on a velocity ramp the output
// is the closed-form step response a (1 - (1 - alpha)^k) of the first-order filter; on a sinusoid it
// has the amplitude and lag of a first-order low-pass at the cutoff.
#include "inertial/signal/causal_acceleration.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace inertial {
namespace {

TEST(CausalAcceleration, RampGivesTheFirstOrderStepResponse) {
  const double dt = 0.002, fc = 20.0;
  const Eigen::Vector2d a(1.5, -4.0);  // qd = a t + qd0: the backward difference is exactly a
  const Eigen::Vector2d qd0(0.3, 2.0);
  CausalAcceleration f(2, fc);
  Eigen::VectorXd qdd = Eigen::VectorXd::Constant(2, 123.0);
  EXPECT_FALSE(f.primed());
  EXPECT_FALSE(f.Update(1.0, qd0, &qdd));
  EXPECT_TRUE(f.primed());
  EXPECT_EQ(qdd, Eigen::VectorXd::Constant(2, 123.0));  // untouched
  const double alpha = dt / (dt + 1.0 / (2 * M_PI * fc));
  for (int k = 1; k <= 200; ++k) {
    const double t = 1.0 + k * dt;
    ASSERT_TRUE(f.Update(t, qd0 + a * (k * dt), &qdd));
    const double response = 1.0 - std::pow(1.0 - alpha, k);
    EXPECT_LT((qdd - a * response).norm(), 1e-9 * a.norm()) << k;
    EXPECT_EQ(f.last_time(), t);
  }
}

// qd = A sin(w t): in steady state the output is the derivative A w cos(w t) filtered by
// 1 / (1 + i w / wc) (small dt): amplitude 1 / sqrt(1 + (w / wc)^2), lag atan(w / wc) (plus the
// half step of the backward difference).
TEST(CausalAcceleration, SinusoidIsLowPassedAtTheCutoff) {
  const double dt = 1e-4, fc = 10.0, f_signal = 3.0, A = 0.8;
  const double w = 2 * M_PI * f_signal, ratio = f_signal / fc;
  const double gain = 1.0 / std::sqrt(1.0 + ratio * ratio), lag = std::atan(ratio) + w * dt / 2;
  CausalAcceleration f(1, fc);
  Eigen::VectorXd qdd(1);
  double worst = 0.0;
  for (int k = 0; k <= 30000; ++k) {
    const double t = k * dt;
    if (!f.Update(t, Eigen::VectorXd::Constant(1, A * std::sin(w * t)), &qdd)) continue;
    if (t < 1.0) continue;  // the transient, e^(-wc t), is long gone after 1 s
    worst = std::max(worst, std::abs(qdd[0] - gain * A * w * std::cos(w * t - lag)));
  }
  EXPECT_LT(worst, 2e-3 * A * w);
}

}  // namespace
}  // namespace inertial
