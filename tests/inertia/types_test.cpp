// types.hpp's one function: Skew(x) y = x cross y, written out, and Skew(x) antisymmetric.
#include "inertial/inertia/types.hpp"

#include <gtest/gtest.h>

#include "test_support.hpp"

namespace inertial {
namespace {

TEST(Types, SkewIsTheCrossProduct) {
  testing::Rng rng(1);
  for (int trial = 0; trial < 20; ++trial) {
    const Vector3 x = rng.UniformVector<3>(-2, 2), y = rng.UniformVector<3>(-2, 2);
    const Vector3 cross(x[1] * y[2] - x[2] * y[1], x[2] * y[0] - x[0] * y[2], x[0] * y[1] - x[1] * y[0]);
    EXPECT_LT(testing::RelativeError(Vector3(Skew(x) * y), cross), 1e-15);
    EXPECT_EQ(Matrix3(Skew(x).transpose()), Matrix3(-Skew(x)));
    EXPECT_LT((Skew(x) * x).norm(), 1e-15);
  }
  Matrix3 expected;
  expected << 0, -3, 2, 3, 0, -1, -2, 1, 0;
  EXPECT_EQ(Skew(Vector3(1, 2, 3)), expected);
}

}  // namespace
}  // namespace inertial
