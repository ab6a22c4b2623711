/// @file bundled_robots.hpp
/// The bundled robots of examples/leg3.urdf, examples/arm7.urdf and examples/chain<n>.urdf written out in code, for
/// programs that use the embeddable core alone (no URDF reader, no file): examples/adaptive_control.cpp
/// and bench/inertial_bench.cpp (built for the robot's own computer). Each link is the plain solid
/// shape its URDF comment gives; tests/formats/bundled_robots_test.cpp checks every joint and inertia
/// against the URDF as the I/O layer loads it.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "inertial/inertia/closed_form_bodies.hpp"
#include "inertial/model/joint_effect.hpp"
#include "inertial/model/kinematic_tree.hpp"
#include "inertial/model/robot_dynamics.hpp"
#include "inertial/model/rotation_from_rpy.hpp"

namespace inertial::examples {

/// A robot's links and the names a model can refer to: joints (one per DOF) and links (fixed links
/// merged into the body they hang on, at their pose in it).
struct BundledRobot {
  KinematicTree links;
  std::vector<std::string> dof_names;
  std::vector<std::pair<std::string, LinkLocation>> link_names;

  /// The model with `effects` (ParseEffectList syntax, e.g. "viscous,coulomb,payload@tool0").
  RobotDynamics Dynamics(const std::string& effects) const {
    const std::vector<std::pair<std::string, LinkLocation>> names = link_names;
    const LinkResolver resolve = [names](const std::string& link, LinkLocation* where) {
      for (const auto& [name, location] : names) {
        if (name == link) {
          *where = location;
          return true;
        }
      }
      return false;
    };
    return RobotDynamics(links, dof_names, ParseEffectList(effects), resolve);
  }
};

namespace detail {

inline JointModel Revolute(const std::string& name, const Vector3& xyz, const Vector3& rpy, const Vector3& axis) {
  JointModel j;
  j.name = name;
  j.type = JointType::kRevolute;
  j.p_parent_joint = xyz;
  j.R_parent_joint = RotationFromRpy(rpy);
  j.axis = axis;
  return j;
}

inline Pose At(const Vector3& xyz, const Vector3& rpy) { return Pose{RotationFromRpy(rpy), xyz}; }

inline BundledRobot Finish(KinematicTree links, const std::string& base,
                           std::vector<std::pair<std::string, LinkLocation>> extra) {
  BundledRobot r;
  r.link_names.push_back({base, LinkLocation{-1, SpatialTransform()}});
  for (int i = 0; i < links.num_bodies(); ++i) {
    r.dof_names.push_back(links.joint(i).name);
    r.link_names.push_back({links.body_name(i), LinkLocation{i, SpatialTransform()}});
  }
  for (auto& e : extra) r.link_names.push_back(std::move(e));
  r.links = std::move(links);
  return r;
}

}  // namespace detail

/// examples/leg3.urdf: a Cheetah-3-like leg, ab/ad about x, hip and knee about y; the foot (a
/// sphere) is part of the shank.
inline BundledRobot Leg3() {
  using detail::At;
  using detail::Revolute;
  constexpr double h = 1.5707963267948966;
  KinematicTree t;
  t.AddBody("abad_link", -1, Revolute("abad", {0.23, 0.05, 0}, {0, 0, 0}, Vector3::UnitX()),
            SolidCylinder(2.0, 0.06, 0.08, At({0, 0.055, 0}, {0, h, 0})));
  t.AddBody("thigh", 0, Revolute("hip", {0, 0.075, 0}, {0, 0, 0}, Vector3::UnitY()),
            SolidBox(1.8, 0.06, 0.05, 0.22, At({0, 0.016, -0.07}, {0, 0.1, 0})));
  t.AddBody("shank", 1, Revolute("knee", {0, 0, -0.34}, {0, 0, 0}, Vector3::UnitY()),
            SolidCylinder(0.45, 0.015, 0.30, At({0, 0, -0.13}, {0, 0, 0})) +
                SolidSphere(0.06, 0.02, At({0, 0, -0.34}, {0, 0, 0})));
  SpatialTransform foot;
  foot.p_AB = Vector3(0, 0, -0.34);
  return detail::Finish(std::move(t), "base", {{"foot", LinkLocation{2, foot}}});
}

/// examples/arm7.urdf: a 7-DOF arm with KUKA-iiwa-like kinematics, every joint about its frame's
/// z axis; tool0 (the flange) 4.5 cm along link7's z.
inline BundledRobot Arm7() {
  using detail::At;
  using detail::Revolute;
  constexpr double h = 1.5707963267948966, p = 3.141592653589793;
  struct Row {
    Vector3 joint_xyz, joint_rpy, com_xyz, com_rpy;
    double mass, radius, length;  // a solid cylinder along its COM frame's z
  };
  const Row rows[7] = {
      {{0, 0, 0.1575}, {0, 0, 0}, {0, -0.03, 0.12}, {0, 0, 0}, 4.0, 0.07, 0.20},
      {{0, 0, 0.2025}, {h, 0, p}, {0.0003, 0.059, 0.042}, {-h, 0, 0}, 4.0, 0.07, 0.20},
      {{0, 0.2045, 0}, {h, 0, p}, {0, 0.03, 0.13}, {0, 0, 0}, 3.0, 0.065, 0.20},
      {{0, 0, 0.2155}, {h, 0, 0}, {0, 0.067, 0.034}, {-h, 0, 0.2}, 2.7, 0.065, 0.20},
      {{0, 0.1845, 0}, {-h, p, 0}, {0.0001, 0.021, 0.076}, {0, 0, 0}, 1.7, 0.055, 0.18},
      {{0, 0, 0.2155}, {h, 0, 0}, {0, 0.0006, 0.0004}, {h, 0, 0}, 1.8, 0.055, 0.10},
      {{0, 0.081, 0}, {-h, p, 0}, {0, 0, 0.02}, {0, 0, 0}, 0.5, 0.04, 0.04},
  };
  KinematicTree t;
  for (int i = 0; i < 7; ++i) {
    const Row& r = rows[i];
    t.AddBody("link" + std::to_string(i + 1), i - 1,
              Revolute("joint" + std::to_string(i + 1), r.joint_xyz, r.joint_rpy, Vector3::UnitZ()),
              SolidCylinder(r.mass, r.radius, r.length, At(r.com_xyz, r.com_rpy)));
  }
  SpatialTransform tool0;
  tool0.p_AB = Vector3(0, 0, 0.045);
  return detail::Finish(std::move(t), "base_link", {{"tool0", LinkLocation{6, tool0}}});
}

/// The serial chain of examples/chain<n>.urdf (scripts/make-chain-urdf.py; the scale benchmarks of
/// bench/inertial_bench.cpp): n revolute joints j1..jn with alternating axes y, x, y, ..., the first
/// 0.05 m above the base and each next one 0.08 m above the last; link i a solid cylinder of radius
/// 0.03 m and length 0.08 m along z, centred 0.04 m above its joint, of mass 0.95^(i-1) kg.
inline BundledRobot Chain(int n) {
  using detail::At;
  using detail::Revolute;
  constexpr double kLength = 0.08, kRadius = 0.03;
  KinematicTree t;
  double mass = 1.0;
  for (int i = 0; i < n; ++i) {
    const Vector3 axis = i % 2 == 0 ? Vector3::UnitY() : Vector3::UnitX();
    t.AddBody("link" + std::to_string(i + 1), i - 1,
              Revolute("j" + std::to_string(i + 1), {0, 0, i == 0 ? 0.05 : kLength}, {0, 0, 0}, axis),
              SolidCylinder(mass, kRadius, kLength, At({0, 0, kLength / 2}, {0, 0, 0})));
    mass *= 0.95;
  }
  return detail::Finish(std::move(t), "base", {});
}

}  // namespace inertial::examples
