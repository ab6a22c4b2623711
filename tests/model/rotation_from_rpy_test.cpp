#include "inertial/model/rotation_from_rpy.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "test_support.hpp"

namespace inertial {
namespace {

// Elementary rotations written out by hand (the reference): R = Rz(yaw) Ry(pitch) Rx(roll).
Matrix3 ByHand(double r, double p, double y) {
  Matrix3 Rx, Ry, Rz;
  Rx << 1, 0, 0, 0, std::cos(r), -std::sin(r), 0, std::sin(r), std::cos(r);
  Ry << std::cos(p), 0, std::sin(p), 0, 1, 0, -std::sin(p), 0, std::cos(p);
  Rz << std::cos(y), -std::sin(y), 0, std::sin(y), std::cos(y), 0, 0, 0, 1;
  return Rz * Ry * Rx;
}

TEST(RotationFromRpy, IsYawPitchRollAboutFixedAxes) {
  testing::Rng rng(3);
  for (int trial = 0; trial < 100; ++trial) {
    const Vector3 rpy = rng.UniformVector<3>(-M_PI, M_PI);
    EXPECT_LT((RotationFromRpy(rpy) - ByHand(rpy.x(), rpy.y(), rpy.z())).cwiseAbs().maxCoeff(), 1e-15) << rpy.transpose();
  }
  // Roll of 90 degrees takes the y axis to z.
  EXPECT_LT((RotationFromRpy(Vector3(M_PI / 2, 0, 0)) * Vector3::UnitY() - Vector3::UnitZ()).norm(), 1e-15);
}

}  // namespace
}  // namespace inertial
