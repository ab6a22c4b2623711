/// @file joint_samples.hpp
/// The joint-space measurement type: a time series of joint positions, velocities, accelerations
/// and torques, the same whatever its source (CSV log, simulator, LCM, CAN).
/// Conventions: rows are samples, columns are joints in joint_names order; SI units (rad or m,
/// rad/s or m/s, rad/s^2 or m/s^2, N m or N); t in seconds, strictly increasing.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

namespace inertial {

struct JointSamples {
  std::vector<std::string> joint_names;
  Eigen::VectorXd t;
  Eigen::MatrixXd q, qd, qdd, tau;
  int size() const { return static_cast<int>(t.size()); }
};

}  // namespace inertial
