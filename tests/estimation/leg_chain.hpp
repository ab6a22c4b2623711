/// @file leg_chain.hpp
/// Test helper: a leg-like chain built in code for the core's identification tests (the core has
/// no URDF reader): ab/ad about x, hip and knee about y, with prior and true link inertias.
#pragma once

#include <string>
#include <vector>

#include "inertial/inertia/closed_form_bodies.hpp"
#include "inertial/model/robot_dynamics.hpp"

namespace inertial::testing {

inline const std::vector<std::string> kLegJoints = {"abad", "hip", "knee"};

/// The chain with the given link inertias (one per joint, in kLegJoints order).
inline KinematicTree LegChain(const std::vector<InertialParams>& links) {
  KinematicTree tree;
  const Vector3 origin[3] = {Vector3(0.2, 0.1, 0), Vector3(0, 0.06, 0), Vector3(0, 0, -0.34)};
  const Vector3 axis[3] = {Vector3::UnitX(), Vector3::UnitY(), Vector3::UnitY()};
  for (int i = 0; i < 3; ++i) {
    JointModel j;
    j.name = kLegJoints[i];
    j.p_parent_joint = origin[i];
    j.axis = axis[i];
    tree.AddBody(kLegJoints[i] + "_link", i - 1, j, links[i]);
  }
  return tree;
}

/// The priors: boxes and a cylinder like a Cheetah leg's.
inline std::vector<InertialParams> LegPriorLinks() {
  return {SolidBox(1.8, 0.12, 0.08, 0.08, Pose{Matrix3::Identity(), Vector3(0.0, 0.04, 0)}),
          SolidBox(1.5, 0.06, 0.06, 0.34, Pose{Matrix3::Identity(), Vector3(0, 0.02, -0.12)}),
          SolidCylinder(0.5, 0.015, 0.34, Pose{Matrix3::Identity(), Vector3(0, 0, -0.16)})};
}

/// The truth: 10-30 % off the priors in mass, centimetres in COM.
inline std::vector<InertialParams> LegTrueLinks() {
  return {SolidBox(2.1, 0.13, 0.07, 0.09, Pose{Matrix3::Identity(), Vector3(0.01, 0.05, -0.01)}),
          SolidBox(1.3, 0.07, 0.05, 0.36, Pose{Matrix3::Identity(), Vector3(0.01, 0.015, -0.14)}),
          SolidCylinder(0.62, 0.02, 0.32, Pose{Matrix3::Identity(), Vector3(0.005, 0, -0.19)})};
}

/// A link resolver that knows no link (no payloads on the chain).
inline LinkResolver NoLinks() {
  return [](const std::string&, LinkLocation*) { return false; };
}

}  // namespace inertial::testing
