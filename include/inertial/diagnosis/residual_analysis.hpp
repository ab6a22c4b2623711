/// @file residual_analysis.hpp
/// Where a joint-space model fails: the residual r = tau_model - tau_measured of each joint,
/// summarized by how it depends on the joint's own signals and by the time windows where it is
/// largest. The dependence is a joint least-squares fit per joint,
///
///   r ~ c0 + c1 sign(qd) + c2 qd + c3 qdd + c4 (q - mean q),
///
/// whose coefficients are the signatures of the physical effects of joint_effect.hpp (with the
/// sign of r: an effect the model lacks shows as minus its torque): c0 an offset, 2 c1 the step at
/// a velocity reversal (Coulomb friction), c2 viscous friction, c3 armature, c4 a spring. Also, for
/// each signal alone (and for the measured torque tau, whose slope is a torque-scale error), the
/// slope of r on it with an intercept, and the correlation.
/// sign(qd) is taken as 0 where |qd| is below 1 % of the joint's velocity RMS.
/// Conventions: rows are samples, columns joints (joint_samples.hpp); SI units.
#pragma once

#include <vector>

#include "inertial/model/joint_samples.hpp"

namespace inertial {

/// The signals of the dependence fit, in the order of its coefficients.
enum ResidualSignal : int { kResidualMean = 0, kVelocitySign, kVelocity, kAcceleration, kPosition, kTorque };
inline constexpr int kResidualSignals = 6;

struct JointResidualSignature {
  double rms = 0.0;
  /// c0..c4 above: [N m], [N m], [N m s/rad], [kg m^2], [N m/rad] (prismatic: N, m, kg);
  /// coefficients[kTorque] is 0 (tau is not in the joint fit: it holds every effect).
  double coefficients[kResidualSignals] = {};
  /// Slope of r on each signal alone (with an intercept); alone[kResidualMean] is the mean of r.
  double alone[kResidualSignals] = {};
  /// Pearson correlation of r with 1 (unused: 0), sign(qd), qd, qdd, q, tau, each alone.
  double correlations[kResidualSignals] = {};
  /// Share of the residual's mean square the dependence fit explains, in [0, 1].
  double explained = 0.0;
};

struct ResidualWindow {
  double t_start = 0.0, t_end = 0.0;
  double rms = 0.0;  ///< over every joint in the window
  int worst_joint = 0;  ///< the joint with the largest RMS in it
};

struct ResidualAnalysis {
  std::vector<JointResidualSignature> joints;
  /// Non-overlapping windows of the requested length, largest RMS first (at most the number asked).
  std::vector<ResidualWindow> worst_windows;
};

/// @param predicted model torques, same shape as data.tau.
/// @throws std::invalid_argument if shapes differ or there are no samples, or window_seconds <= 0.
ResidualAnalysis AnalyzeResiduals(const JointSamples& data, const Eigen::MatrixXd& predicted, double window_seconds,
                                  int num_windows);

}  // namespace inertial
