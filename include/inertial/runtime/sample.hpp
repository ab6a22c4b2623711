/// @file sample.hpp
/// What flows through the sample pipeline (source -> decode -> preprocess -> estimator -> sinks):
/// a joint-space sample of a robot, or a single body's twist and wrench. One type for both, so the
/// queue, the replay loop and the pipeline are the same code for a robot and for a body.
#pragma once

#include "inertial/model/body_sample.hpp"
#include "inertial/model/joint_samples.hpp"

namespace inertial {

/// A robot's sample (`joint`) or a body's (`body`): which one is the pipeline's mode, fixed when it
/// is made; the other member is unused.
struct Sample {
  JointSample joint;
  BodySample body;

  /// A robot's sample with its vectors sized for n joints (so that copies into it never allocate).
  static Sample ForJoints(int n) {
    Sample s;
    s.joint.q = s.joint.qd = s.joint.qdd = s.joint.tau = Eigen::VectorXd::Zero(n);
    return s;
  }
  double time(bool body_mode) const { return body_mode ? body.t : joint.t; }
};

}  // namespace inertial
