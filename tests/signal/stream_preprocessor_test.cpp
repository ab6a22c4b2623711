#include "inertial/signal/stream_preprocessor.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace inertial {
namespace {

JointSample Make(double t, const Eigen::Vector2d& qd, bool has_qdd) {
  JointSample s;
  s.t = t;
  s.q = Eigen::VectorXd::Zero(2);
  s.qd = qd;
  s.qdd = has_qdd ? Eigen::VectorXd(Eigen::Vector2d(7.0, -7.0)) : Eigen::VectorXd::Zero(2);
  s.tau = Eigen::VectorXd::Zero(2);
  s.has_qdd = has_qdd;
  return s;
}

TEST(StreamPreprocessor, MeasuredAccelerationsPassUnchanged) {
  StreamPreprocessor p(2, 20.0);
  JointSample s = Make(0.0, Eigen::Vector2d(1, 2), true);
  ASSERT_EQ(p.Process(&s), Rejection::kNone);  // no priming: nothing to derive
  EXPECT_EQ(s.qdd, Eigen::VectorXd(Eigen::Vector2d(7.0, -7.0)));
}

TEST(StreamPreprocessor, DerivesMissingAccelerationsByTheLowPassedDifference) {
  const double fc = 30.0, dt = 0.01;
  StreamPreprocessor p(2, fc);
  JointSample s = Make(1.0, Eigen::Vector2d(0, 0), false);
  std::string why;
  EXPECT_EQ(p.Process(&s, &why), Rejection::kPriming);
  EXPECT_NE(why.find("primes"), std::string::npos) << why;
  s = Make(1.0 + dt, Eigen::Vector2d(0.5, 1.5), false);
  ASSERT_EQ(p.Process(&s), Rejection::kNone);
  EXPECT_TRUE(s.has_qdd);
  // A first-order low pass from rest: alpha = dt / (dt + 1 / (2 pi fc)) of the difference quotient.
  const double alpha = dt / (dt + 1.0 / (2 * M_PI * fc));
  EXPECT_NEAR(s.qdd[0], alpha * 0.5 / dt, 1e-12);
  EXPECT_NEAR(s.qdd[1], alpha * 1.5 / dt, 1e-12);
}

// A stream at 100 Hz with late samples (3.4 steps: jitter, differentiated as usual) and a 0.5 s
// pause (50 steps): after the pause the filter starts again, so the sample after it only primes and
// the next one's qdd is a fresh filter's, bit for bit.
TEST(StreamPreprocessor, AGapIsNotDifferentiatedAcross) {
  const double fc = 30.0;
  StreamPreprocessor p(2, fc);
  double t = 0.0;
  auto qd = [](double time) { return Eigen::Vector2d(std::sin(3 * time), std::cos(2 * time)); };
  for (int i = 0; i < 40; ++i, t += (i % 10 == 5 ? 0.034 : 0.01)) {
    JointSample s = Make(t, qd(t), false);
    EXPECT_EQ(p.Process(&s), i == 0 ? Rejection::kPriming : Rejection::kNone) << i;
  }
  t += 0.5;
  JointSample after = Make(t, qd(t), false);
  std::string why;
  EXPECT_EQ(p.Process(&after, &why), Rejection::kPriming);
  EXPECT_NE(why.find("a gap in the stream"), std::string::npos) << why;
  JointSample next = Make(t + 0.01, qd(t + 0.01), false);
  ASSERT_EQ(p.Process(&next), Rejection::kNone);
  CausalAcceleration fresh(2, fc);
  Eigen::VectorXd qdd(2);
  fresh.Update(t, Eigen::VectorXd(qd(t)), &qdd);
  fresh.Update(t + 0.01, Eigen::VectorXd(qd(t + 0.01)), &qdd);
  EXPECT_EQ(next.qdd, qdd);
}

TEST(StreamPreprocessor, RefusesTimeThatDoesNotAdvanceAndWrongSizes) {
  StreamPreprocessor p(2, 20.0);
  JointSample s = Make(2.0, Eigen::Vector2d(0, 0), true);
  ASSERT_EQ(p.Process(&s), Rejection::kNone);
  for (double t : {2.0, 1.0, std::nan("")}) {
    s = Make(t, Eigen::Vector2d(0, 0), true);
    EXPECT_EQ(p.Process(&s), Rejection::kOutOfOrder) << t;
  }
  s = Make(3.0, Eigen::Vector2d(0, 0), true);
  s.qd.resize(3);
  EXPECT_EQ(p.Process(&s), Rejection::kWrongSize);
  s = Make(3.0, Eigen::Vector2d(0, 0), true);
  EXPECT_EQ(p.Process(&s), Rejection::kNone);  // a refused sample does not move the clock
}

TEST(StreamPreprocessor, AnOverflowingDerivativeIsRefusedAndTheFilterStartsAgain) {
  StreamPreprocessor p(2, 20.0);
  const double huge = std::numeric_limits<double>::max();
  JointSample s = Make(0.0, Eigen::Vector2d(-huge, 0), false);
  EXPECT_EQ(p.Process(&s), Rejection::kPriming);
  s = Make(1e-9, Eigen::Vector2d(huge, 0), false);
  EXPECT_EQ(p.Process(&s), Rejection::kNonFinite);
  s = Make(2e-9, Eigen::Vector2d(0, 0), false);
  EXPECT_EQ(p.Process(&s), Rejection::kPriming);  // restarted: this one primes again
  s = Make(1e-3, Eigen::Vector2d(0, 0), false);
  ASSERT_EQ(p.Process(&s), Rejection::kNone);
  EXPECT_TRUE(s.qdd.allFinite());
}

}  // namespace
}  // namespace inertial
