#include "inertial/inertia/closed_form_bodies.hpp"

#include <gtest/gtest.h>

#include <functional>

#include "test_support.hpp"

namespace inertial {
namespace {

using testing::RelativeError;
using testing::Rng;

// Pseudo-inertia J = integral of q q^T rho (eq. 6) by midpoint quadrature on an n^3 grid over the
// box [-h, h]^3 of the body's own frame, for a uniform density filling `inside`.
Matrix4 QuadraturePseudoInertia(double mass, const Vector3& half, const std::function<bool(const Vector3&)>& inside,
                                int n) {
  Matrix4 J = Matrix4::Zero();
  double volume_cells = 0.0;
  const Vector3 step = 2.0 * half / n;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k) {
        const Vector3 x = -half + Vector3((i + 0.5) * step.x(), (j + 0.5) * step.y(), (k + 0.5) * step.z());
        if (!inside(x)) continue;
        Vector4 q;
        q << x, 1.0;
        J += q * q.transpose();
        volume_cells += 1.0;
      }
  return mass * J / volume_cells;  // uniform density: each cell carries mass / cells
}

TEST(ClosedFormBodies, MatchQuadratureOfTheirShapes) {
  const int n = 120;
  struct Case {
    const char* name;
    InertialParams body;
    Vector3 half;
    std::function<bool(const Vector3&)> inside;
    double tolerance;
  };
  const double r = 0.2, l = 0.7, a = 0.3, b = 0.15, c = 0.45;
  const std::vector<Case> cases = {
      {"box", SolidBox(2.0, 0.4, 0.6, 0.8), Vector3(0.2, 0.3, 0.4), [](const Vector3&) { return true; }, 1e-3},
      {"cylinder", SolidCylinder(1.5, r, l), Vector3(r, r, l / 2),
       [&](const Vector3& x) { return x.x() * x.x() + x.y() * x.y() <= r * r; }, 1e-2},
      {"sphere", SolidSphere(3.0, r), Vector3(r, r, r), [&](const Vector3& x) { return x.norm() <= r; }, 1e-2},
      {"ellipsoid", SolidEllipsoid(0.8, a, b, c), Vector3(a, b, c),
       [&](const Vector3& x) { return std::pow(x.x() / a, 2) + std::pow(x.y() / b, 2) + std::pow(x.z() / c, 2) <= 1.0; },
       1e-2},
  };
  for (const Case& k : cases) {
    const Matrix4 J = QuadraturePseudoInertia(k.body.mass(), k.half, k.inside, n);
    EXPECT_LT(RelativeError(k.body.pseudo_inertia(), J), k.tolerance) << k.name;
  }
}

TEST(ClosedFormBodies, PoseIsATransformOfTheCentredBody) {
  Rng rng(4);
  for (int trial = 0; trial < 100; ++trial) {
    const Pose pose = rng.RandomPose<Pose>(1.0);
    const InertialParams centred = SolidCylinder(1.2, 0.1, 0.5);
    const InertialParams placed = SolidCylinder(1.2, 0.1, 0.5, pose);
    EXPECT_LT(RelativeError(placed.vector(), centred.Transformed(pose.R_BC, pose.p_BoCo_B).vector()), 1e-14);
    EXPECT_LT(RelativeError(placed.com(), pose.p_BoCo_B), 1e-14);
  }
}

TEST(ClosedFormBodies, TextbookMoments) {
  // Sphere: 2/5 m r^2; cylinder about its axis: m r^2 / 2, across: m (3 r^2 + l^2) / 12.
  const Matrix3 Is = SolidSphere(2.0, 0.5).rotational_inertia_about_origin();
  EXPECT_NEAR(Is(0, 0), 0.4 * 2.0 * 0.25, 1e-15);
  const Matrix3 Ic = SolidCylinder(3.0, 0.2, 1.0).rotational_inertia_about_origin();
  EXPECT_NEAR(Ic(2, 2), 0.5 * 3.0 * 0.04, 1e-15);
  EXPECT_NEAR(Ic(0, 0), 3.0 * (3 * 0.04 + 1.0) / 12.0, 1e-15);
}

TEST(ClosedFormBodies, RejectInvalidDimensions) {
  EXPECT_THROW(SolidBox(1.0, 0.0, 1.0, 1.0), std::invalid_argument);
  EXPECT_THROW(SolidSphere(-1.0, 1.0), std::invalid_argument);
  EXPECT_THROW(SolidCylinder(1.0, std::nan(""), 1.0), std::invalid_argument);
  try {
    SolidEllipsoid(1.0, 1.0, -2.0, 1.0);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("semi_axis_y"), std::string::npos);
  }
}

}  // namespace
}  // namespace inertial
