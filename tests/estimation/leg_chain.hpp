/// @file leg_chain.hpp
/// Test helper: a leg-like chain built in code for the core's identification tests (the core has
/// no URDF reader): ab/ad about x, hip and knee about y, with prior and true link inertias.
#pragma once

#include <cmath>
#include <string>
#include <vector>

#include "inertial/inertia/closed_form_bodies.hpp"
#include "inertial/model/joint_samples.hpp"
#include "inertial/model/robot_dynamics.hpp"
#include "test_support.hpp"

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

/// The tests' excitation of the leg: N samples every dt seconds along a sum of three sinusoids per
/// joint (exact derivatives; `phase` shifts them, for a held-out trajectory), torques from
/// `truth` at x_true plus Gaussian noise of std `noise` [N m].
inline JointSamples ExciteLeg(const RobotDynamics& truth, const Eigen::VectorXd& x_true, int N, double dt, double noise,
                              Rng& rng, double phase = 0.0) {
  JointSamples s;
  s.joint_names = kLegJoints;
  s.t.resize(N);
  s.q.resize(N, 3);
  s.qd.resize(N, 3);
  s.qdd.resize(N, 3);
  s.tau.resize(N, 3);
  for (int k = 0; k < N; ++k) {
    const double t = k * dt;
    s.t[k] = t;
    for (int j = 0; j < 3; ++j) {
      s.q(k, j) = s.qd(k, j) = s.qdd(k, j) = 0.0;
      for (int h = 1; h <= 3; ++h) {
        const double w = 2 * M_PI * 0.3 * h * (1 + 0.37 * j), a = 0.5 / h, p = phase + j + h;
        s.q(k, j) += a * std::sin(w * t + p);
        s.qd(k, j) += a * w * std::cos(w * t + p);
        s.qdd(k, j) -= a * w * w * std::sin(w * t + p);
      }
    }
    s.tau.row(k) = truth.InverseDynamics(x_true, s.q.row(k).transpose(), s.qd.row(k).transpose(),
                                         s.qdd.row(k).transpose()).transpose();
    for (int j = 0; j < 3; ++j) s.tau(k, j) += noise * rng.Normal();
  }
  return s;
}

}  // namespace inertial::testing
