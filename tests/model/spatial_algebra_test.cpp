// Spatial cross products against their definitions with 3D cross products (Featherstone 2008,
// angular first): xi x m = [w x mw; v x mw + w x mv], xi x* f = [w x fn + v x ff; w x ff], and their
// duality (xi x m) . f = -m . (xi x* f).
#include "inertial/model/spatial_algebra.hpp"

#include <gtest/gtest.h>

#include "test_support.hpp"

namespace inertial {
namespace {

using testing::RelativeError;
using testing::Rng;

// The 3D cross product, written out.
Vector3 Cross(const Vector3& a, const Vector3& b) {
  return Vector3(a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]);
}

TEST(SpatialAlgebra, ForceCrossIsMinusTransposedMotionCross) {
  Rng rng(4);
  const Vector6 xi = rng.UniformVector<6>(-1.0, 1.0);
  EXPECT_LT(RelativeError(ForceCross(xi), Matrix6(-MotionCross(xi).transpose())), 1e-16);
  // xi x xi = 0.
  EXPECT_LT((MotionCross(xi) * xi).norm(), 1e-15);
}

TEST(SpatialAlgebra, CrossProductsAreTheirDefinitionsAndDual) {
  Rng rng(5);
  for (int trial = 0; trial < 20; ++trial) {
    const Vector6 xi = rng.UniformVector<6>(-2, 2), m = rng.UniformVector<6>(-2, 2), f = rng.UniformVector<6>(-2, 2);
    const Vector3 w = xi.head<3>(), v = xi.tail<3>();
    const Vector3 mw = m.head<3>(), mv = m.tail<3>(), fn = f.head<3>(), ff = f.tail<3>();
    Vector6 motion, force;
    motion << Cross(w, mw), Cross(v, mw) + Cross(w, mv);
    force << Cross(w, fn) + Cross(v, ff), Cross(w, ff);
    EXPECT_LT(RelativeError(Vector6(MotionCross(xi) * m), motion), 1e-15);
    EXPECT_LT(RelativeError(Vector6(ForceCross(xi) * f), force), 1e-15);
    EXPECT_NEAR((MotionCross(xi) * m).dot(f), -m.dot(ForceCross(xi) * f), 1e-13);
    // Skew is the 3D cross product.
    EXPECT_LT(RelativeError(Vector3(Skew(w) * v), Cross(w, v)), 1e-15);
  }
}

}  // namespace
}  // namespace inertial
