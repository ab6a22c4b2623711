#include "inertial/inertia/nearest_consistent.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "inconsistent_bodies.hpp"
#include "inertial/inertia/consistency.hpp"

namespace inertial {
namespace {

Matrix3 SecondMomentsAboutCom(const InertialParams& b) {
  const Matrix3 I = b.rotational_inertia_about_com();
  return 0.5 * I.trace() * Matrix3::Identity() - I;
}

// Every inconsistent body with positive, finite mass is repaired to a consistent one with the same
// mass and COM; the others are refused with a reason.
TEST(NearestConsistent, RepairsWhatCanBeRepairedKeepingMassAndCom) {
  int repaired_count = 0;
  for (const Vector10& pi : testing::InconsistentBodies(51)) {
    const InertialParams body = InertialParams::FromVector(pi);
    InertialParams repaired = SolidSphere(1, 1);
    std::string why;
    const bool ok = NearestConsistentBody(body, &repaired, &why);
    if (!body.AllFinite() || !(body.mass() > 0)) {
      EXPECT_FALSE(ok);
      EXPECT_FALSE(why.empty());
      continue;
    }
    ASSERT_TRUE(ok);
    ++repaired_count;
    EXPECT_TRUE(CheckConsistency(repaired).fully_consistent()) << CheckConsistency(repaired).reason;
    EXPECT_NEAR(repaired.mass(), body.mass(), 1e-12 * body.mass());
    EXPECT_LT((repaired.com() - body.com()).norm(), 1e-9 * (1 + body.com().norm()));
  }
  EXPECT_GT(repaired_count, 500);
}

TEST(NearestConsistent, LeavesConsistentBodiesAlone) {
  const InertialParams box = SolidBox(2.0, 0.1, 0.2, 0.3, Pose{Matrix3::Identity(), Vector3(0.1, 0, 0)});
  InertialParams out = SolidSphere(1, 1);
  ASSERT_TRUE(NearestConsistentBody(box, &out));
  EXPECT_EQ(out.vector(), box.vector());
}

// Nearest: no consistent body with the same mass and COM and second moments >= eps is closer (in
// the Frobenius norm of Sigma_c) than the repaired one. Checked against random such candidates.
TEST(NearestConsistent, NoRandomCandidateIsCloser) {
  testing::Rng rng(52);
  const InertialParams bad = BodyFromSecondMoments(1.5, Vector3(0.02, 0.01, -0.004),
                                                   Pose{rng.Rotation(), Vector3(0.1, 0.2, -0.1)});
  InertialParams repaired = bad;
  ASSERT_TRUE(NearestConsistentBody(bad, &repaired));
  const Matrix3 S_bad = SecondMomentsAboutCom(bad);
  const double d_repaired = (SecondMomentsAboutCom(repaired) - S_bad).norm();
  const double eps = std::max(1e-3 * 0.02, 1.5e-6);
  for (int k = 0; k < 2000; ++k) {
    const Matrix3 R = rng.Rotation();
    const Vector3 s = (rng.UniformVector<3>(0, 0.03)).cwiseMax(eps);
    const Matrix3 S = R * s.asDiagonal() * R.transpose();
    EXPECT_GE((S - S_bad).norm(), d_repaired - 1e-12);
  }
  EXPECT_NEAR(d_repaired, 0.004 + eps, 1e-9);  // only the negative moment moves, to eps
}

}  // namespace
}  // namespace inertial
