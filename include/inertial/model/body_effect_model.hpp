/// @file body_effect_model.hpp
/// One rigid body measured by a twist sensor and a wrench sensor, with the sensor effects a real
/// rig has (Rucker & Wensing 2022, Section VI adds a velocity bias to its simulated data):
///
///   w_measured = Y(xi_measured - b_v, xi_dot, g_B + g_u) pi(theta) + [b_m; b_f],
///
/// per pair of samples by the paper's midpoint rule (eq. 13: xi at the midpoint, xi_dot the
/// difference quotient, w and g averaged; midpoint_regression.hpp). Effects:
///   force_bias     b_f [N]       a constant force on the sensor reading (offset, cable drag)
///   moment_bias    b_m [N m]     a constant moment on the sensor reading
///   velocity_bias  b_v (6)       a constant bias of the measured twist [rad/s, m/s] (eq. 13 with
///                                xi - b_v); the derivative is unaffected
///   gravity        g_u [m/s^2]   gravity (or a constant frame acceleration) the model lacks,
///                                constant in the body frame
/// x = [theta (10, log-Cholesky relative to the prior, eq. 11); each effect's parameters in list
/// order]. Conventions: twist [omega; v], wrench [moment; force], body frame, SI units; residual
/// = predicted - measured.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "inertial/inertia/log_cholesky.hpp"
#include "inertial/model/midpoint_regression.hpp"

namespace inertial {

enum class BodyEffectKind { kForceBias, kMomentBias, kVelocityBias, kGravity };

/// "force_bias", "moment_bias", "velocity_bias", "gravity".
std::string_view ToString(BodyEffectKind kind);
/// Number of parameters: 3, 3, 6, 3.
int ParameterCount(BodyEffectKind kind);
/// Parses a comma-separated list of the names above.
/// @throws std::invalid_argument naming an unknown or repeated item.
std::vector<BodyEffectKind> ParseBodyEffectList(std::string_view text);

/// A single-body log: samples in time order, and gravity in the body frame per sample (empty: no
/// gravity, a free body).
struct BodyLog {
  std::vector<TwistWrenchSample> samples;
  std::vector<Vector3> gravity;
  int num_pairs() const { return samples.empty() ? 0 : static_cast<int>(samples.size()) - 1; }
};

class BodyEffectModel {
 public:
  /// @throws std::invalid_argument if an effect is repeated.
  BodyEffectModel(const InertialParams& prior, std::vector<BodyEffectKind> effects);

  int num_parameters() const { return num_parameters_; }
  const std::vector<BodyEffectKind>& effects() const { return effects_; }
  int first_parameter(int effect) const { return first_parameter_[effect]; }
  const InertialParams& prior() const { return prior_; }
  /// "alpha", "d1", ..., "force_bias.x", "velocity_bias.wx", ...
  std::vector<std::string> ParameterNames() const;

  InertialParams Body(const Eigen::VectorXd& x) const;
  /// The parameters of effect k at x.
  Eigen::VectorXd EffectValues(int k, const Eigen::VectorXd& x) const;

  /// Predicted wrench of pair i (samples i, i+1) and optionally its Jacobian (6 x num_parameters).
  /// Preconditions: 0 <= i < log.num_pairs(), strictly increasing time, sizes as documented.
  Vector6 PredictPair(const Eigen::VectorXd& x, const BodyLog& log, int i, Eigen::MatrixXd* J_w_x = nullptr) const;
  /// The measured (averaged) wrench of pair i.
  static Vector6 MeasuredPair(const BodyLog& log, int i);
  /// Residuals (predicted - measured) of every pair: rows = pairs, columns = [mx my mz fx fy fz].
  Eigen::MatrixXd Residuals(const Eigen::VectorXd& x, const BodyLog& log) const;

 private:
  InertialParams prior_;
  LogCholeskyParameterization map_;
  std::vector<BodyEffectKind> effects_;
  std::vector<int> first_parameter_;
  int num_parameters_ = 10;
};

}  // namespace inertial
