#include "inertial/inertia/bounding_ellipsoid.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <stdexcept>

#include "inertial/inertia/closed_form_bodies.hpp"
#include "test_support.hpp"

namespace inertial {
namespace {

Matrix3 RandomRotation(testing::Rng& rng) {
  const Vector3 axis = rng.UniformVector<3>(-1, 1).normalized();  // before the angle, as on x86-64 (see testing::Rng)
  return Eigen::AngleAxisd(rng.Uniform(-M_PI, M_PI), axis).toRotationMatrix();
}

// A solid ellipsoid's region is itself: its slack is 1 - E[|u|^2] over the unit ball = 1 - 3/5 = 0.4
// (a uniform ball's mean squared radius is 3/5 of its radius squared), whatever its pose and mass.
TEST(BoundingEllipsoid, ASolidEllipsoidInItselfHasSlackTwoFifths) {
  testing::Rng rng(1);
  for (int k = 0; k < 20; ++k) {
    const Matrix3 R = RandomRotation(rng);
    const Vector3 c = rng.UniformVector<3>(-1, 1), a = rng.UniformVector<3>(0.02, 0.5);
    const InertialParams body = SolidEllipsoid(rng.Uniform(0.1, 20), a.x(), a.y(), a.z(), Pose{R, c});
    const BoundingEllipsoid region = BoundingEllipsoid::FromAxes(c, R, a);
    EXPECT_NEAR(region.Slack(body), 0.4, 1e-9) << k;
    // Its equivalent uniform ellipsoid is itself.
    const BoundingEllipsoid same = EquivalentUniformEllipsoid(body);
    EXPECT_NEAR((same.center - c).norm(), 0.0, 1e-12);
    EXPECT_LT((same.shape_inverse - region.shape_inverse).norm(), 1e-8 * region.shape_inverse.norm()) << k;
    EXPECT_NEAR(region.Volume(), 4.0 / 3.0 * M_PI * a.prod(), 1e-12 * a.prod());
    // tr(Q J) is the linear function q . pi.
    EXPECT_NEAR(region.RegionCoefficients().dot(body.vector()), (region.Q() * body.pseudo_inertia()).trace(),
                1e-12 * body.mass());
  }
}

// A point mass (a tiny sphere) at normalized radius r has slack 1 - r^2: inside for r < 1, outside
// beyond; the boundary is the ellipsoid's surface.
TEST(BoundingEllipsoid, ASmallSphereCrossesTheBoundaryAtTheSurface) {
  const BoundingEllipsoid region = BoundingEllipsoid::FromAxes(Vector3(0.1, 0, 0), Matrix3::Identity(), Vector3(0.4, 0.1, 0.2));
  for (double r : {0.0, 0.5, 0.9, 1.1, 2.0}) {
    const InertialParams tiny = SolidSphere(2.0, 1e-5, Pose{Matrix3::Identity(), Vector3(0.1 + 0.4 * r, 0, 0)});
    EXPECT_NEAR(region.Slack(tiny), 1.0 - r * r, 1e-8) << r;
    EXPECT_EQ(region.Contains(tiny.com()), r <= 1.0) << r;
  }
  // A rod along the long axis from the centre to the surface: E[x^2] = a^2 / 3.
  const InertialParams rod = SolidCylinder(1.0, 1e-5, 0.4, Pose{Eigen::AngleAxisd(M_PI / 2, Vector3::UnitY()).toRotationMatrix(),
                                                               Vector3(0.3, 0, 0)});
  EXPECT_NEAR(region.Slack(rod), 1.0 - 1.0 / 3.0, 1e-6);
}

// The smallest ellipsoid around a box's corners is the box's circumscribed ellipsoid, semi-axes
// sqrt(3) times the half sizes (the box's symmetry makes it the John ellipsoid); around a regular
// octahedron's vertices, the sphere through them.
TEST(BoundingEllipsoid, SmallestAroundABoxAndAnOctahedron) {
  testing::Rng rng(2);
  const Matrix3 R = RandomRotation(rng);
  const Vector3 c(0.3, -0.2, 0.5), h(0.1, 0.25, 0.05);
  std::vector<Vector3> corners;
  for (int i = 0; i < 8; ++i) {
    corners.push_back(c + R * Vector3((i & 1 ? 1 : -1) * h.x(), (i & 2 ? 1 : -1) * h.y(), (i & 4 ? 1 : -1) * h.z()));
  }
  const BoundingEllipsoid box = MinimumVolumeEllipsoid(corners, 1e-7);
  EXPECT_LT((box.center - c).norm(), 1e-5);
  const Vector3 expected = std::sqrt(3.0) * Vector3(0.05, 0.1, 0.25);
  EXPECT_LT((box.SemiAxes() - expected).cwiseAbs().maxCoeff(), 1e-4) << box.SemiAxes().transpose();
  for (const Vector3& p : corners) EXPECT_TRUE(box.Contains(p));

  std::vector<Vector3> octahedron;
  for (int i = 0; i < 3; ++i) {
    octahedron.push_back(c + 0.2 * Vector3::Unit(i));
    octahedron.push_back(c - 0.2 * Vector3::Unit(i));
  }
  const BoundingEllipsoid ball = MinimumVolumeEllipsoid(octahedron, 1e-7);
  EXPECT_LT((ball.SemiAxes() - Vector3::Constant(0.2)).cwiseAbs().maxCoeff(), 1e-4);
  // Any 4+ points inside a known ellipsoid: the smallest one is no larger.
  std::vector<Vector3> inside;
  const BoundingEllipsoid known = BoundingEllipsoid::FromAxes(c, R, Vector3(0.3, 0.2, 0.1));
  for (int i = 0; i < 50; ++i) {
    Vector3 u = rng.UniformVector<3>(-1, 1);
    if (u.norm() > 1) u.normalize();
    inside.push_back(c + R * Vector3(0.3, 0.2, 0.1).cwiseProduct(u));
  }
  const BoundingEllipsoid around = MinimumVolumeEllipsoid(inside);
  EXPECT_LE(around.Volume(), known.Volume() * (1 + 1e-3));
  for (const Vector3& p : inside) EXPECT_TRUE(around.Contains(p));
}

TEST(BoundingEllipsoid, RefusesWhatDeterminesNoEllipsoid) {
  EXPECT_THROW(MinimumVolumeEllipsoid({Vector3(0, 0, 0), Vector3(1, 0, 0), Vector3(0, 1, 0)}), std::invalid_argument);
  EXPECT_THROW(MinimumVolumeEllipsoid({Vector3(0, 0, 0), Vector3(1, 0, 0), Vector3(0, 1, 0), Vector3(1, 1, 0)}),
               std::invalid_argument);
  EXPECT_THROW(MinimumVolumeEllipsoid({Vector3(0, 0, 0), Vector3(1, 0, 0), Vector3(0, 1, 0), Vector3(0, 0, NAN)}),
               std::invalid_argument);
  EXPECT_THROW(BoundingEllipsoid::FromAxes(Vector3::Zero(), Matrix3::Identity(), Vector3(1, 0, 1)), std::invalid_argument);
  EXPECT_EQ(BoundingEllipsoid().Slack(InertialParams()), -std::numeric_limits<double>::infinity());
}

}  // namespace
}  // namespace inertial
