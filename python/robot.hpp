// The Python module's Robot: a URDF robot with its effects, as the CLI loads it.
#pragma once

#include <string>
#include <vector>

#include "inertial/formats/model_file.hpp"
#include "inertial/model/robot_dynamics.hpp"

namespace inertial::python {

struct Robot {
  std::string urdf;
  RobotModel model;
  std::vector<EffectSpec> effects;
  RobotDynamics dynamics;

  /// The URDF's links and the effects it declares plus `effects` (the CLI's --effects text).
  /// @throws pybind11::value_error with the CLI's message (an unknown file, a bad effect list).
  static Robot FromUrdf(const std::string& path, const std::string& effects, const Vector3& gravity);
  /// Writes the model at x (identify's x) as a model file to `path` (never over the robot's URDF).
  /// @throws pybind11::value_error naming the file.
  void WriteUrdf(const Eigen::VectorXd& x, const std::string& path, const std::string& origin) const;
};

}  // namespace inertial::python
