/// @file replay_config.hpp
/// How `inertial replay` is set up: the replay's options (log_replay.hpp) and the estimator's,
/// first from inertiald's --config file (its channel, message format, publish rate, residual
/// window, estimator, noise and tuning: the replay runs the daemon's estimator), then the command
/// line's values over them (given as plain values: the command line is parsed by the program).
#pragma once

#include <optional>
#include <string>

#include "inertial/estimation/online/online_joint_estimator.hpp"
#include "inertial/runtime/log_replay.hpp"

namespace inertial {

struct ReplayConfig {
  ReplayOptions replay;
  OnlineEstimatorOptions estimator;
};

/// The command line's values; unset (empty) ones keep the configuration's.
struct ReplayOverrides {
  std::optional<double> noise_tau;        ///< estimator.measurement_sigma [N m]
  std::optional<double> publish_rate_hz;  ///< replay.estimate_period_s = 1 / publish_rate_hz
  std::optional<double> time_scale;       ///< replay.csv.time_scale
  std::optional<EstimatorKind> estimator; ///< estimator.kind
  std::string channel;                    ///< replay.channel (empty: the configuration's)
  bool realtime = false;                  ///< replay.realtime (always applied)
  std::string csv_path;                   ///< replay.csv_path (always applied)
  std::string log_path;                   ///< replay.log_path (always applied)
};

/// The defaults, with the daemon configuration at `config_path` (empty: none) applied: channel,
/// format, estimator options, estimate_period_s = 1 / publish_rate_hz, residual_window_s.
/// @throws std::runtime_error (a file error) "--config: cannot read the configuration '<path>': ..."
/// or "--config: <path>: <why>" (not JSON, not a valid configuration).
ReplayConfig ReplayConfigFromFile(const std::string& config_path);

/// The command line's values over *config.
void ApplyReplayOverrides(const ReplayOverrides& overrides, ReplayConfig* config);

}  // namespace inertial
