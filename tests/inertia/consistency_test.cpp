#include "inertial/inertia/consistency.hpp"

#include <gtest/gtest.h>

#include "inertial/inertia/closed_form_bodies.hpp"
#include "test_support.hpp"

namespace inertial {
namespace {

using testing::Rng;

TEST(Consistency, SolidBodiesAreConsistentWithExactMargins) {
  Rng rng(1);
  for (int trial = 0; trial < 500; ++trial) {
    const Pose pose = rng.RandomPose<Pose>(1.0);
    const double m = rng.Uniform(0.1, 5.0);
    const Vector3 L = rng.UniformVector<3>(0.01, 1.0);
    const ConsistencyReport r = CheckConsistency(BodyFromSecondMoments(m, L, pose));
    EXPECT_TRUE(r.fully_consistent()) << r.reason;
    EXPECT_TRUE(r.reason.empty());
    EXPECT_DOUBLE_EQ(r.mass, m);
    // D = [Ly+Lz, Lx+Lz, Lx+Ly]; the smallest triangle margin is 2 min(L) (eq. 5).
    EXPECT_NEAR(r.min_triangle_margin, 2.0 * L.minCoeff(), 1e-12);
    Vector3 D(L.y() + L.z(), L.x() + L.z(), L.x() + L.y());
    std::sort(D.data(), D.data() + 3);
    EXPECT_LT((r.principal_moments_com - D).norm(), 1e-12);
    EXPECT_GT(r.min_pseudo_inertia_eigenvalue, 0.0);
  }
}

TEST(Consistency, DegenerateBodiesAreNotFullyConsistent) {
  Rng rng(2);
  for (int trial = 0; trial < 100; ++trial) {
    const Pose pose = rng.RandomPose<Pose>(1.0);
    const double m = rng.Uniform(0.1, 5.0);
    const double a = rng.Uniform(0.01, 1.0), b = rng.Uniform(0.01, 1.0);
    const ConsistencyReport point = CheckConsistency(BodyFromSecondMoments(m, Vector3::Zero(), pose));
    const ConsistencyReport rod = CheckConsistency(BodyFromSecondMoments(m, Vector3(0, 0, a), pose));
    const ConsistencyReport plate = CheckConsistency(BodyFromSecondMoments(m, Vector3(a, b, 0), pose));
    for (const ConsistencyReport* r : {&point, &rod, &plate}) {
      EXPECT_FALSE(r->fully_consistent());
      EXPECT_TRUE(r->mass_positive);
      EXPECT_FALSE(r->triangle_inequalities);
      EXPECT_FALSE(r->pseudo_inertia_positive_definite);
      EXPECT_NE(r->reason.find("triangle inequality"), std::string::npos) << r->reason;
    }
    // A plate's inertia is still positive definite: only the triangle inequality catches it.
    EXPECT_TRUE(plate.inertia_positive_definite_com);
  }
}

TEST(Consistency, ReportsEachViolationWithItsMargin) {
  // Principal moments (1, 1, 3) violate 1 + 1 > 3 by -1 though I is positive definite.
  Matrix3 I = Vector3(1.0, 1.0, 3.0).asDiagonal();
  ConsistencyReport r = CheckConsistency(InertialParams::FromMassComInertia(2.0, Vector3(0.5, 0, 0), I));
  EXPECT_FALSE(r.fully_consistent());
  EXPECT_TRUE(r.inertia_positive_definite_com);
  EXPECT_FALSE(r.triangle_inequalities);
  EXPECT_NEAR(r.min_triangle_margin, -1.0, 1e-14);
  EXPECT_NE(r.reason.find("-1"), std::string::npos) << r.reason;

  // Negative mass.
  Vector10 pi = SolidBox(1.0, 0.1, 0.2, 0.3).vector();
  pi[pi_index::kMass] = -0.5;
  r = CheckConsistency(InertialParams::FromVector(pi));
  EXPECT_FALSE(r.mass_positive);
  EXPECT_NE(r.reason.find("mass not positive: m = -0.5"), std::string::npos) << r.reason;

  // Not positive definite.
  I = Vector3(-0.1, 1.0, 1.0).asDiagonal();
  r = CheckConsistency(InertialParams::FromMassComInertia(1.0, Vector3::Zero(), I));
  EXPECT_FALSE(r.inertia_positive_definite_com);
  EXPECT_FALSE(r.inertia_positive_definite_origin);
  EXPECT_NEAR(r.min_inertia_eigenvalue_com, -0.1, 1e-15);

  // NaN.
  pi[pi_index::kIyz] = std::nan("");
  r = CheckConsistency(InertialParams::FromVector(pi));
  EXPECT_FALSE(r.finite);
  EXPECT_FALSE(r.fully_consistent());
  EXPECT_NE(r.reason.find("non-finite"), std::string::npos);
}

// Theorem II.1 and J > 0 agree (Wensing et al. 2018): random perturbations are classified the same
// way by the triangle/eigenvalue test and by the pseudo-inertia.
TEST(Consistency, TriangleTestAgreesWithPseudoInertia) {
  Rng rng(3);
  int consistent = 0, inconsistent = 0;
  for (int trial = 0; trial < 5000; ++trial) {
    Vector10 pi = SolidBox(1.0, 0.3, 0.4, 0.5, Pose{rng.Rotation(), rng.UniformVector<3>(-0.2, 0.2)}).vector();
    pi.tail<6>() += rng.UniformVector<6>(-0.008, 0.008);
    const ConsistencyReport r = CheckConsistency(InertialParams::FromVector(pi));
    const bool by_triangle = r.inertia_positive_definite_com && r.triangle_inequalities;
    EXPECT_EQ(by_triangle, r.pseudo_inertia_positive_definite) << pi.transpose();
    (r.fully_consistent() ? consistent : inconsistent)++;
  }
  EXPECT_GT(consistent, 500);
  EXPECT_GT(inconsistent, 500);
}

}  // namespace
}  // namespace inertial
