/// @file joint_samples.hpp
/// The joint-space measurement types: one sample (JointSample, what an online source delivers) and a
/// time series of joint positions, velocities, accelerations
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

/// One joint-space sample: time [s] and per DOF q, qd, qdd, tau (SI units, the model's DOF order).
struct JointSample {
  double t = 0.0;
  Eigen::VectorXd q, qd, qdd, tau;
  /// False: the source did not measure qdd (it holds zeros); the preprocessing stage
  /// (stream_preprocessor.hpp) derives it before the estimator sees the sample.
  bool has_qdd = true;
  /// False: qdd was not measured but derived (by the preprocessing stage, or from q when a CSV
  /// log was read) or is absent. The online estimator then fits rows that need no qdd
  /// (momentum_rows.hpp) and never the derived qdd, which lags or smooths; consumers that want an
  /// acceleration (the stream diagnosis) still find the derived one in qdd.
  bool qdd_measured = true;
};

/// Sample i of a joint log (joint_samples.hpp) as a JointSample; reuses *out's memory when sizes
/// match. Precondition: 0 <= i < log.size().
void CopySample(const JointSamples& log, int i, JointSample* out);

}  // namespace inertial
