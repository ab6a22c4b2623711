/// @file daemon_config.hpp
/// inertiald's settings: the options of the daemon (runtime/estimation_daemon.hpp) and their
/// --config JSON file, read with nlohmann-json; every key checked.
#pragma once

#include <cstddef>
#include <nlohmann/json.hpp>
#include <string>

#include "inertial/estimation/online_joint_estimator.hpp"
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
  JointMessageFormat format;
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
/// "publish_rate_hz", "residual_window_s", "checkpoint", "checkpoint_interval_s", "queue_capacity",
/// "estimator", "measurement_sigma", "log_level", "format": {...joint_message.hpp...}}; absent keys
/// keep *options' values. @throws std::invalid_argument naming the key.
void ApplyDaemonConfig(const nlohmann::json& config, DaemonOptions* options);

}  // namespace inertial
