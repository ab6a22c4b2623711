/// @file rotation_from_rpy.hpp
/// URDF's orientation convention, for the URDF reader and robots written out in code.
#pragma once

#include <Eigen/Geometry>

#include "inertial/inertia/types.hpp"

namespace inertial {

/// The rotation of URDF's rpy = (roll, pitch, yaw), fixed axes: R = Rz(yaw) Ry(pitch) Rx(roll).
inline Matrix3 RotationFromRpy(const Vector3& rpy) {
  return (Eigen::AngleAxisd(rpy.z(), Vector3::UnitZ()) * Eigen::AngleAxisd(rpy.y(), Vector3::UnitY()) *
          Eigen::AngleAxisd(rpy.x(), Vector3::UnitX()))
      .toRotationMatrix();
}

}  // namespace inertial
