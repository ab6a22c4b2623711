// The linear (identity) map: x = pi both ways, identity Jacobian, any finite vector accepted
// (impossible bodies included), non-finite ones refused with x untouched.
#include "inertial/inertia/linear_parameterization.hpp"

#include <gtest/gtest.h>

#include <limits>

#include "test_support.hpp"

namespace inertial {
namespace {

TEST(LinearParameterization, IsTheIdentityAndRefusesOnlyNonFiniteVectors) {
  const LinearParameterization map;
  EXPECT_EQ(map.name(), "linear");
  testing::Rng rng(2);
  Vector10 x;
  for (int i = 0; i < 10; ++i) x[i] = rng.Uniform(-3, 3);  // mostly not a physical body
  Matrix10 J = Matrix10::Zero();
  EXPECT_EQ(map.ToPi(x, &J), x);
  EXPECT_EQ(J, Matrix10::Identity());
  Vector10 back = Vector10::Zero();
  ASSERT_TRUE(map.FromPi(x, &back));
  EXPECT_EQ(back, x);
  Vector10 bad = x;
  bad[4] = std::numeric_limits<double>::infinity();
  EXPECT_FALSE(map.FromPi(bad, &back));
  EXPECT_EQ(back, x);
}

}  // namespace
}  // namespace inertial
