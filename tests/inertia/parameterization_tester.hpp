/// @file parameterization_tester.hpp
/// The properties every map x -> pi(x) of parameterization.hpp must have, written once and run for
/// each (parameterization_test.cpp instantiates them, as manif's common tester does for its Lie
/// groups): the exact Jacobian against central differences, the round trip pi -> x -> pi, the
/// refusal of bodies outside the image (leaving x untouched), and the consistency of what FromPi
/// gives. A map states what it guarantees through a traits struct:
///   static P Make();                 the map under test
///   static constexpr bool kConsistent = ...;  FromPi refuses every inconsistent body
///   static constexpr bool kToleratesRounding = ...;  (consistent maps) a body on the boundary only
///       up to rounding may be accepted, if pi(x) gives it back (log-Cholesky's FromPi is a
///       Cholesky factorization without a tolerance; CheckConsistency is the gate before it)
#pragma once

#include <gtest/gtest.h>

#include <vector>

#include <Eigen/Eigenvalues>

#include "inconsistent_bodies.hpp"
#include "inertial/inertia/closed_form_bodies.hpp"
#include "inertial/inertia/consistency.hpp"
#include "test_support.hpp"

namespace inertial::testing {

/// Well-conditioned consistent bodies: boxes, cylinders and ellipsoids of 0.1 to 10 kg, 5 cm to
/// 1 m, in random poses within 0.5 m.
inline std::vector<InertialParams> ConditionedBodies(unsigned seed, int n) {
  Rng rng(seed);
  std::vector<InertialParams> bodies;
  for (int k = 0; k < n; ++k) {
    const Pose pose = rng.RandomPose<Pose>(0.5);
    const double m = rng.Uniform(0.1, 10.0);
    // One draw per statement, the last dimension first, as the x86-64 build drew them (see Rng).
    switch (k % 3) {
      case 0: {
        const double z = rng.Uniform(0.05, 1);
        const double y = rng.Uniform(0.05, 1);
        const double x = rng.Uniform(0.05, 1);
        bodies.push_back(SolidBox(m, x, y, z, pose));
        break;
      }
      case 1: {
        const double length = rng.Uniform(0.05, 1);
        const double radius = rng.Uniform(0.025, 0.5);
        bodies.push_back(SolidCylinder(m, radius, length, pose));
        break;
      }
      default: {
        const double c = rng.Uniform(0.025, 0.5);
        const double b = rng.Uniform(0.025, 0.5);
        const double a = rng.Uniform(0.025, 0.5);
        bodies.push_back(SolidEllipsoid(m, a, b, c, pose));
      }
    }
  }
  return bodies;
}

/// Largest entry of |a - b| over the largest entry of |b| (at least 1e-300).
template <typename M>
double ScaledError(const M& a, const M& b) {
  return (a - b).cwiseAbs().maxCoeff() / std::max(b.cwiseAbs().maxCoeff(), 1e-300);
}

template <typename Traits>
class ParameterizationTester : public ::testing::Test {};
TYPED_TEST_SUITE_P(ParameterizationTester);

// Central differences with h = 1e-6 have a truncation error of order h^2 |pi'''| / 6 and a rounding
// error of order eps |pi| / h = 2e-10 |pi|: on these bodies (x of order 1, derivatives of order
// |pi|) both are far below 1e-6 of the largest entry, while a wrong column or sign is of order 1.
TYPED_TEST_P(ParameterizationTester, JacobianMatchesCentralDifferences) {
  const auto map = TypeParam::Make();
  const std::function<Vector10(const Vector10&)> f = [&](const Vector10& x) { return map.ToPi(x); };
  for (const InertialParams& body : ConditionedBodies(11, 150)) {
    Vector10 x;
    ASSERT_TRUE(map.FromPi(body.vector(), &x)) << map.name();
    Matrix10 J;
    const Vector10 pi = map.ToPi(x, &J);
    EXPECT_EQ(pi, map.ToPi(x)) << map.name() << ": asking for J changed pi";
    EXPECT_LT(ScaledError(J, CentralDifference<10, 10>(f, x)), 1e-6) << map.name() << " at x = " << x.transpose();
  }
}

// pi(FromPi(pi)) = pi to rounding: the bodies' entries span about 3 orders of magnitude, and the
// maps use decompositions of 4 x 4 matrices (Cholesky, eigenvalues, matrix exp/log), backward
// stable to a few hundred eps of the largest entry.
TYPED_TEST_P(ParameterizationTester, RoundTripPiXPi) {
  const auto map = TypeParam::Make();
  for (const InertialParams& body : ConditionedBodies(12, 300)) {
    Vector10 x;
    ASSERT_TRUE(map.FromPi(body.vector(), &x)) << map.name();
    EXPECT_LT(ScaledError(map.ToPi(x), body.vector()), 1e-12) << map.name() << " " << body.vector().transpose();
    if (TypeParam::kConsistent) EXPECT_TRUE(map.YieldsConsistentBody(x)) << map.name();
  }
}

TYPED_TEST_P(ParameterizationTester, RefusesBodiesOutsideItsImageAndLeavesXUntouched) {
  const auto map = TypeParam::Make();
  const Vector10 sentinel = Vector10::Constant(42.0);
  int refused = 0, total = 0;
  for (const Vector10& pi : InconsistentBodies(13)) {
    Vector10 x = sentinel;
    const bool finite = pi.allFinite();
    const bool accepted = map.FromPi(pi, &x);
    ++total;
    if (!accepted) {
      ++refused;
      EXPECT_EQ(x, sentinel) << map.name() << ": a refusal changed x";
    }
    if (!finite || !TypeParam::kConsistent) {
      EXPECT_EQ(accepted, finite) << map.name() << " " << pi.transpose();  // the linear map: only NaN and Inf
      continue;
    }
    if (!accepted) continue;
    // Accepted although inconsistent: allowed only for a map that tolerates rounding, and only for
    // a body whose pseudo-inertia is singular to rounding (a few eps of its largest eigenvalue),
    // which it must then represent exactly.
    const Eigen::SelfAdjointEigenSolver<Matrix4> eig(InertialParams::FromVector(pi).pseudo_inertia());
    const double rounding = 64 * 2.2e-16 * eig.eigenvalues().cwiseAbs().maxCoeff();
    EXPECT_TRUE(TypeParam::kToleratesRounding) << map.name() << " accepted " << pi.transpose();
    EXPECT_GT(eig.eigenvalues()[0], -rounding) << map.name() << " accepted a clearly inconsistent " << pi.transpose();
    EXPECT_LT(ScaledError(map.ToPi(x), pi), 1e-9) << map.name();
  }
  if (TypeParam::kConsistent && !TypeParam::kToleratesRounding) EXPECT_EQ(refused, total) << map.name();
  if (TypeParam::kConsistent) EXPECT_GE(refused, 7) << map.name();  // the bodies inconsistent by more than rounding
}

REGISTER_TYPED_TEST_SUITE_P(ParameterizationTester, JacobianMatchesCentralDifferences, RoundTripPiXPi,
                            RefusesBodiesOutsideItsImageAndLeavesXUntouched);

}  // namespace inertial::testing
