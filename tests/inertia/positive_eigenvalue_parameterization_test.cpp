#include "inertial/inertia/positive_eigenvalue_parameterization.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "inertial/inertia/closed_form_bodies.hpp"
#include "inertial/inertia/consistency.hpp"
#include "inconsistent_bodies.hpp"
#include "test_support.hpp"

namespace inertial {
namespace {

using testing::CentralDifference;
using testing::RelativeError;
using testing::Rng;

TEST(PositiveEigenvalue, MapsToTheBodyOfTheseMassesMomentsAndPose) {
  Rng rng(1);
  const PositiveEigenvalueParameterization p;
  for (int trial = 0; trial < 500; ++trial) {
    const Vector10 x = rng.UniformVector<10>(-2.0, 2.0);
    const Vector3 beta = x.segment<3>(phi_index::kBeta1);
    Pose pose;
    pose.R_BC = Eigen::AngleAxisd(beta.norm(), beta.normalized()).toRotationMatrix();
    pose.p_BoCo_B = x.segment<3>(phi_index::kCx);
    const Vector3 L(std::exp(x[phi_index::kLx]), std::exp(x[phi_index::kLy]), std::exp(x[phi_index::kLz]));
    const InertialParams expected = BodyFromSecondMoments(std::exp(x[phi_index::kMass]), L, pose);
    EXPECT_LT(RelativeError(p.ToPi(x), expected.vector()), 1e-12);
    EXPECT_TRUE(p.YieldsConsistentBody(x));
    EXPECT_TRUE(IsPhysicallyConsistent(expected));
  }
}

TEST(PositiveEigenvalue, JacobianMatchesCentralDifferences) {
  Rng rng(2);
  const PositiveEigenvalueParameterization p;
  const std::function<Vector10(const Vector10&)> f = [&](const Vector10& x) { return p.ToPi(x); };
  for (int trial = 0; trial < 300; ++trial) {
    const Vector10 x = rng.UniformVector<10>(-2.0, 2.0);
    Matrix10 J;
    p.ToPi(x, &J);
    EXPECT_LT(RelativeError(J, CentralDifference<10, 10>(f, x)), 1e-6);
  }
}

TEST(PositiveEigenvalue, RoundTripAndRefusal) {
  Rng rng(3);
  const PositiveEigenvalueParameterization p;
  for (int trial = 0; trial < 500; ++trial) {
    // One draw per statement, in the order the x86-64 build drew them (see testing::Rng).
    const Pose pose{rng.Rotation(), rng.UniformVector<3>(-0.5, 0.5)};
    const Vector3 L = rng.UniformVector<3>(0.01, 1.0);
    const double mass = rng.Uniform(0.1, 2.0);
    const InertialParams body = BodyFromSecondMoments(mass, L, pose);
    Vector10 x;
    ASSERT_TRUE(p.FromPi(body.vector(), &x));
    EXPECT_LT(RelativeError(p.ToPi(x), body.vector()), 1e-10);
  }
  Vector10 x = Vector10::Constant(7.0);
  for (const Vector10& pi : testing::InconsistentBodies(4)) {
    EXPECT_FALSE(p.FromPi(pi, &x)) << pi.transpose();
    EXPECT_EQ(x, Vector10::Constant(7.0));
  }
}

}  // namespace
}  // namespace inertial
