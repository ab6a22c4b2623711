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
