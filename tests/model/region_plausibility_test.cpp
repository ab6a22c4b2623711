#include "inertial/model/region_plausibility.hpp"

#include <gtest/gtest.h>

#include <string>

#include "inertial/inertia/closed_form_bodies.hpp"

namespace inertial {
namespace {

// A region of semi-axes 0.3, 0.1, 0.1 m about the origin (volume 4/3 pi 0.003 m^3).
BodyRegion Region() {
  BodyRegion r;
  r.ellipsoid = BoundingEllipsoid::FromAxes(Vector3::Zero(), Matrix3::Identity(), Vector3(0.3, 0.1, 0.1));
  r.max_mass = kMaxRegionDensity * r.ellipsoid.Volume();
  r.source = RegionSource::kSegment;
  return r;
}

// Closed-form bodies against the verdicts of the header: a solid ellipsoid filling the region
// (slack 2/5), the same four times heavier, a small ball outside, one near the surface.
TEST(RegionPlausibility, VerdictsOfClosedFormBodies) {
  const BodyRegion region = Region();
  const InertialParams prior = SolidEllipsoid(2.0, 0.3, 0.1, 0.1);
  const RegionPlausibility same = JudgeAgainstRegion(prior, prior, region);
  EXPECT_NEAR(same.slack, 0.4, 1e-9);
  EXPECT_NEAR(same.density, 2.0 / region.ellipsoid.Volume(), 1e-9);
  EXPECT_TRUE(same.plausible && same.inside && !same.on_edge);
  EXPECT_TRUE(same.words.empty());

  const RegionPlausibility heavy = JudgeAgainstRegion(SolidEllipsoid(8.0, 0.3, 0.1, 0.1), prior, region);
  EXPECT_NEAR(heavy.mass_ratio, 4.0, 1e-12);
  EXPECT_TRUE(heavy.inside);
  EXPECT_FALSE(heavy.plausible);
  EXPECT_NE(heavy.words.find("4 times the URDF's 2 kg"), std::string::npos) << heavy.words;
  // A payload's prior is a guess: its mass is not judged against it.
  EXPECT_TRUE(JudgeAgainstRegion(SolidEllipsoid(8.0, 0.3, 0.1, 0.1), prior, region, false).plausible);

  const InertialParams outside = SolidSphere(2.0, 0.01, Pose{Matrix3::Identity(), Vector3(0, 0.2, 0)});
  const RegionPlausibility out = JudgeAgainstRegion(outside, prior, region);
  EXPECT_LT(out.slack, 0.0);
  EXPECT_FALSE(out.inside || out.plausible);
  EXPECT_NE(out.words.find("outside its region (joints and prior)"), std::string::npos) << out.words;

  // Normalized radius 0.99: slack 1 - 0.98 = 0.02, inside but on the edge (plausible, with words).
  const InertialParams edge = SolidSphere(2.0, 1e-4, Pose{Matrix3::Identity(), Vector3(0.297, 0, 0)});
  const RegionPlausibility e = JudgeAgainstRegion(edge, prior, region);
  EXPECT_TRUE(e.inside && e.on_edge && e.plausible);
  EXPECT_NE(e.words.find("held on the edge"), std::string::npos) << e.words;

  const RegionPlausibility dense = JudgeAgainstRegion(SolidEllipsoid(2.0 * region.max_mass, 0.3, 0.1, 0.1), prior, region);
  EXPECT_FALSE(dense.inside);
  EXPECT_NE(dense.words.find("denser than steel"), std::string::npos) << dense.words;
}

// Whether the mass was compared is recorded with the verdict: a payload's guessed prior, or a body
// that is its own reference, is not judged by its mass however far from the prior's it is.
TEST(RegionPlausibility, RecordsWhetherTheMassWasCompared) {
  const InertialParams prior = SolidBox(2.0, 0.2, 0.05, 0.05);
  const InertialParams heavy = SolidBox(8.0, 0.2, 0.05, 0.05);
  const RegionPlausibility drawn = JudgeAgainstRegion(heavy, prior, Region(), true);
  EXPECT_TRUE(drawn.mass_compared);
  EXPECT_FALSE(drawn.plausible);
  const RegionPlausibility guessed = JudgeAgainstRegion(heavy, prior, Region(), false);
  EXPECT_FALSE(guessed.mass_compared);
  EXPECT_TRUE(guessed.plausible) << guessed.words;
  EXPECT_DOUBLE_EQ(guessed.mass_ratio, 4.0);
}

}  // namespace
}  // namespace inertial
