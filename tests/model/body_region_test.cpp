#include "inertial/model/body_region.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "inertial/inertia/closed_form_bodies.hpp"
#include "inertial/model/robot_dynamics.hpp"
#include "test_support.hpp"

namespace inertial {
namespace {

// The 26 points of ShapePointsOfSphere circumscribe the ball: their smallest ellipsoid holds every
// point of a fine sampling of the sphere (and is at most 1/0.9 times its radius).
TEST(BodyRegion, SpherePointsCircumscribeTheBall) {
  const Vector3 c(0.1, -0.2, 0.3);
  const BoundingEllipsoid e = MinimumVolumeEllipsoid(ShapePointsOfSphere(c, 0.07));
  for (int i = 0; i <= 40; ++i) {
    for (int j = 0; j < 80; ++j) {
      const double polar = M_PI * i / 40, azimuth = 2 * M_PI * j / 80;
      const Vector3 u(std::sin(polar) * std::cos(azimuth), std::sin(polar) * std::sin(azimuth), std::cos(polar));
      EXPECT_TRUE(e.Contains(c + 0.07 * u)) << i << " " << j;
    }
  }
  EXPECT_LE(e.SemiAxes().maxCoeff(), 0.07 / 0.9 * (1 + 1e-6));
  // A cylinder's 24 points hold its rims.
  const Matrix3 R = Eigen::AngleAxisd(0.4, Vector3(1, 2, 3).normalized()).toRotationMatrix();
  const BoundingEllipsoid cyl = MinimumVolumeEllipsoid(ShapePointsOfCylinder(R, c, 0.05, 0.3));
  for (int j = 0; j < 100; ++j) {
    const double a = 2 * M_PI * j / 100;
    for (double z : {-0.15, 0.15}) EXPECT_TRUE(cyl.Contains(c + R * Vector3(0.05 * std::cos(a), 0.05 * std::sin(a), z)));
  }
}

KinematicTree TwoLinks(const InertialParams& upper, const InertialParams& lower) {
  KinematicTree tree;
  JointModel j;
  j.name = "shoulder";
  j.axis = Vector3::UnitY();
  tree.AddBody("upper", -1, j, upper);
  j.name = "elbow";
  j.p_parent_joint = Vector3(0, 0, -0.4);
  tree.AddBody("lower", 0, j, lower);
  return tree;
}

// A link's segment region holds its joint, its child's joint and its prior, each with the margin; its
// mass bound is steel over the region.
TEST(BodyRegion, SegmentRegionHoldsTheJointsAndThePrior) {
  const InertialParams upper = SolidCylinder(3.0, 0.04, 0.4, Pose{Matrix3::Identity(), Vector3(0, 0, -0.2)});
  const InertialParams lower = SolidCylinder(1.0, 0.03, 0.3, Pose{Matrix3::Identity(), Vector3(0, 0, -0.15)});
  const KinematicTree tree = TwoLinks(upper, lower);
  const BodyRegion r = SegmentRegion(tree, 0, upper);
  EXPECT_EQ(r.source, RegionSource::kSegment);
  EXPECT_TRUE(r.ellipsoid.Contains(Vector3::Zero()));
  EXPECT_TRUE(r.ellipsoid.Contains(Vector3(0, 0, -0.4)));
  EXPECT_GT(r.ellipsoid.Slack(upper), 0.3);  // the prior well inside
  EXPECT_NEAR(r.max_mass, kMaxRegionDensity * r.ellipsoid.Volume(), 1e-9);
  // The region is the link's size, not the robot's: a point 0.3 m beside the link is outside.
  EXPECT_FALSE(r.ellipsoid.Contains(Vector3(0.3, 0, -0.2)));
  // The same body 0.3 m aside is outside (negative slack).
  EXPECT_LT(r.ellipsoid.Slack(upper.Transformed(Matrix3::Identity(), Vector3(0.3, 0, 0))), 0.0);
}

// RobotDynamics gives every link a region, a payload a ball of the robot's longest segment about its
// link, and a rotor none; a region that does not hold the prior is refused.
TEST(BodyRegion, EveryEstimatedBodyButRotorsHasOne) {
  const InertialParams upper = SolidCylinder(3.0, 0.04, 0.4, Pose{Matrix3::Identity(), Vector3(0, 0, -0.2)});
  const InertialParams lower = SolidCylinder(1.0, 0.03, 0.3, Pose{Matrix3::Identity(), Vector3(0, 0, -0.15)});
  const LinkResolver resolve = [](const std::string& link, LinkLocation* where) {
    if (link != "lower") return false;
    where->body = 1;
    return true;
  };
  RobotDynamics model(TwoLinks(upper, lower), {"shoulder", "elbow"},
                      ParseEffectList("payload@lower,rotor@elbow:gear=10"), resolve);
  int with = 0;
  for (const EstimatedBody& b : model.bodies()) {
    if (b.name.rfind("rotor@", 0) == 0) {
      EXPECT_FALSE(b.region.has_value()) << b.name;
      continue;
    }
    ASSERT_TRUE(b.region.has_value()) << b.name;
    ++with;
    EXPECT_GT(b.region->ellipsoid.Slack(b.prior), 0.0) << b.name;
    if (b.name == "payload@lower") {
      EXPECT_EQ(b.region->source, RegionSource::kPayloadReach);
      EXPECT_TRUE(b.region->ellipsoid.Contains(Vector3(0.39, 0, 0)));
      EXPECT_FALSE(b.region->ellipsoid.Contains(Vector3(0.6, 0, 0)));
    }
  }
  EXPECT_EQ(with, 3);
  BodyRegion far;
  far.ellipsoid = BoundingEllipsoid::FromAxes(Vector3(2, 0, 0), Matrix3::Identity(), Vector3::Constant(0.1));
  far.max_mass = 100;
  EXPECT_THROW(model.SetBodyRegion(0, far), std::invalid_argument);
  model.SetBodyRegion(0, std::nullopt);
  EXPECT_FALSE(model.bodies()[0].region.has_value());
}

// The region of points alone: a box's 8 corners give the ellipsoid through them (semi-axes sqrt(3)
// times the half sizes), grown by the margin, with no prior added; it need not hold any body.
TEST(BodyRegion, RegionOfPointsAloneIsTheirEllipsoid) {
  const std::vector<Vector3> corners = ShapePointsOfBox(Matrix3::Identity(), Vector3(0, 0, 0.2), Vector3(0.1, 0.1, 0.4));
  const BodyRegion r = RegionOfPoints(corners, 0.1, RegionSource::kShape);
  EXPECT_EQ(r.source, RegionSource::kShape);
  EXPECT_LT((r.ellipsoid.center - Vector3(0, 0, 0.2)).norm(), 1e-3);
  const Vector3 axes = r.ellipsoid.SemiAxes();
  EXPECT_NEAR(axes[2], 1.1 * std::sqrt(3.0) * 0.2, 2e-3);
  EXPECT_NEAR(axes[0], 1.1 * std::sqrt(3.0) * 0.05, 2e-3);
  EXPECT_NEAR(r.max_mass, kMaxRegionDensity * r.ellipsoid.Volume(), 1e-9);
  // A COM 0.3 m beside the box lies outside it (RegionAround would have grown to hold such a prior).
  EXPECT_LT(r.ellipsoid.Slack(SolidSphere(1.0, 0.01, Pose{Matrix3::Identity(), Vector3(0, 0.3, 0.2)})), 0.0);
  EXPECT_THROW(RegionOfPoints({Vector3::Zero(), Vector3::UnitX(), Vector3::UnitY()}, 0.1, RegionSource::kShape),
               std::invalid_argument);
}

}  // namespace
}  // namespace inertial
