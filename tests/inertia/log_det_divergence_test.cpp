#include "inertial/inertia/log_det_divergence.hpp"

#include <gtest/gtest.h>

#include "inertial/inertia/closed_form_bodies.hpp"
#include "test_support.hpp"

namespace inertial {
namespace {

using testing::Rng;

InertialParams RandomBody(Rng& rng) {
  // One draw per statement, in the order the x86-64 build drew them (see testing::Rng).
  const Pose pose{rng.Rotation(), rng.UniformVector<3>(-0.3, 0.3)};
  const Vector3 L = rng.UniformVector<3>(1e-3, 0.1);
  return BodyFromSecondMoments(rng.Uniform(0.1, 5.0), L, pose);
}

// ||r||^2 equals tr(J0^-1 J) - log det(J0^-1 J) - 4 computed from the two pseudo-inertias.
TEST(LogDetDivergence, SquaredResidualsEqualTheDivergence) {
  Rng rng(11);
  for (int trial = 0; trial < 500; ++trial) {
    const InertialParams prior = RandomBody(rng);
    const LogCholeskyParameterization map(prior);
    const Vector10 theta = rng.UniformVector<10>(-1.5, 1.5) * (trial % 3 == 0 ? 1e-3 : 1.0);
    const Matrix4 J = PseudoInertiaFromPi(map.ToPi(theta));
    const double expected = LogDetDivergence(J, prior.pseudo_inertia());
    const double d = LogDetDivergenceResiduals(map, theta).squaredNorm();
    EXPECT_NEAR(d, expected, 1e-9 * (1.0 + expected)) << "trial " << trial;
  }
}

TEST(LogDetDivergence, ZeroAtThePriorAndPositiveElsewhere) {
  Rng rng(12);
  const LogCholeskyParameterization map(RandomBody(rng));
  EXPECT_LT(LogDetDivergenceResiduals(map, Vector10::Zero()).norm(), 1e-15);  // U0^-1 U0 rounds
  for (int trial = 0; trial < 100; ++trial) {
    EXPECT_GT(LogDetDivergenceResiduals(map, rng.UniformVector<10>(-1, 1)).squaredNorm(), 0.0);
  }
}

// The Jacobian against central differences, including near x_i = 0 where the series branch is used.
TEST(LogDetDivergence, JacobianMatchesFiniteDifferences) {
  Rng rng(13);
  for (int trial = 0; trial < 200; ++trial) {
    const LogCholeskyParameterization map(RandomBody(rng));
    const double scale = trial % 2 == 0 ? 1.0 : 5e-3;  // the second half straddles the series branch
    const Vector10 theta = rng.UniformVector<10>(-1, 1) * scale;
    Matrix10 J;
    LogDetDivergenceResiduals(map, theta, &J);
    const Matrix10 J_fd = testing::CentralDifference<10, 10>(
        [&](const Vector10& t) { return LogDetDivergenceResiduals(map, t); }, theta, 1e-6);
    EXPECT_LT((J - J_fd).cwiseAbs().maxCoeff(), 1e-7 * (1.0 + J.cwiseAbs().maxCoeff())) << "trial " << trial;
  }
}

// Coordinate invariance (the reason the paper uses it): moving estimate and prior by the same rigid
// transform leaves the divergence unchanged, although pi changes.
TEST(LogDetDivergence, InvariantUnderAChangeOfFrame) {
  Rng rng(14);
  for (int trial = 0; trial < 100; ++trial) {
    const InertialParams prior = RandomBody(rng);
    const InertialParams estimate = RandomBody(rng);
    const Matrix3 R = rng.Rotation();
    const Vector3 p = rng.UniformVector<3>(-1, 1);
    const double d = LogDetDivergence(estimate.pseudo_inertia(), prior.pseudo_inertia());
    const double d_moved =
        LogDetDivergence(estimate.Transformed(R, p).pseudo_inertia(), prior.Transformed(R, p).pseudo_inertia());
    EXPECT_NEAR(d, d_moved, 1e-8 * (1.0 + d));
  }
}

}  // namespace
}  // namespace inertial
