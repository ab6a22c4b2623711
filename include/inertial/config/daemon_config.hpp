/// @file daemon_config.hpp
/// inertiald's settings: the options of the daemon (runtime/estimation_daemon.hpp) and their
/// --config JSON file, read with nlohmann-json; every key checked.
#pragma once

#include <cstddef>
#include <nlohmann/json.hpp>
#include <string>

#include "inertial/estimation/online/online_joint_estimator.hpp"
#include "inertial/transport/joint_message.hpp"

namespace inertial {

enum class LogLevel { kError = 0, kWarn = 1, kInfo = 2, kDebug = 3 };
/// "error", "warn", "info", "debug". @throws std::invalid_argument for others.
LogLevel ParseLogLevel(const std::string& name);

struct DaemonOptions {
  std::string lcm_url;                              ///< empty: LCM's default (udpm://239.255.76.67:7667)
  std::string input_channel = "INERTIAL_JOINT_STATE";
  std::string estimate_channel = "INERTIAL_ESTIMATE";
  std::string residual_channel;                     ///< empty: no per-sample residual messages
  /// Robot mode: the online diagnosis (stream_diagnosis.hpp) in its own thread, published as
  /// inertial.diagnosis_t on this channel every diagnosis_period_s seconds and logged at exit;
  /// empty: no diagnosis.
  std::string diagnosis_channel = "INERTIAL_DIAGNOSIS";
  double diagnosis_period_s = 5.0;
  /// Robot mode, any estimator: payloads picked up or put down (payload_event.hpp) published as
  /// inertial.payload_event_t on this channel and logged; empty: none.
  std::string payload_channel = "INERTIAL_PAYLOAD_EVENT";
  JointMessageFormat format;
  /// Per DOF: the gain of the logged torques (gain@joint of the model file); empty: N m. Set from the
  /// model file, not from --config.
  Eigen::VectorXd log_gains;
  double publish_rate_hz = 10.0;
  double residual_window_s = 1.0;
  std::string checkpoint_path;                      ///< empty: no checkpoints
  /// An existing checkpoint that cannot be restored (unreadable, of another model or estimator, or
  /// not a usable state) stops the start, leaving the file untouched, unless this is set: then the
  /// estimator starts from the priors and the file is overwritten at the next checkpoint.
  bool start_fresh = false;
  double checkpoint_interval_s = 5.0;
  std::size_t queue_capacity = 4096;
  OnlineEstimatorOptions estimator;
  LogLevel log_level = LogLevel::kInfo;
};

/// From the --config JSON: {"lcm_url", "channel", "estimate_channel", "residual_channel",
/// "diagnosis_channel", "diagnosis_period_s", "payload_channel" ("" turns the diagnosis or the
/// payload events off),
/// "publish_rate_hz", "residual_window_s", "checkpoint", "checkpoint_interval_s", "queue_capacity",
/// "estimator", "noise_tau", "log_level", "format": {...joint_message.hpp...}, "tuning": {...}};
/// absent keys keep *options' values. "noise_tau" is the torque noise standard deviation the
/// estimator assumes [N m] (the CLI's --noise-tau). "tuning" holds the estimator's own settings, each
/// optional (defaults of kalman_update.hpp, gradient_estimator.hpp, online_joint_estimator.hpp):
///   theta_std [1] 0.3: initial std of every log-Cholesky parameter, > 0
///   effect_std [1] 1: initial std of every effect parameter, > 0
///   forgetting [1] 1: lambda in (0, 1], P /= lambda per sample (Gauss-Newton, linear RLS)
///   process_noise [parameter^2] 0: added to P's diagonal per sample, >= 0 (idem)
///   max_variance_factor [1] 1: cap of P_ii under forgetting and process noise, times its initial value, >= 1
///   huber [sigma] 3: normalized innovation where down-weighting starts, > 0
///   gate [sigma] 30: normalized innovation beyond which a sample is an outlier, > huber
///   max_consecutive_outliers [samples] 50: more in a row is a change (P reset; the gradient law's
///     statistics restarted), integer >= 1
///   max_step [parameter] 0.5: bound on |dx|_inf per sample, > 0 (gradient 0.1: the relative change
///     of a body's J, |gamma S_b|_F, and |dx|_inf of the effects)
///   gain [1] 1: the gradient law's step over the exact minimizer along its direction, in (0, 2)
/// @throws std::invalid_argument naming the key and its range.
void ApplyDaemonConfig(const nlohmann::json& config, DaemonOptions* options);

}  // namespace inertial
