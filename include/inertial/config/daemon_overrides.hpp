/// @file daemon_overrides.hpp
/// inertiald's command-line settings over its options: each value as the command line gave it
/// (text; empty: not given, the --config's or the default value stays), checked and applied over a
/// DaemonOptions (daemon_config.hpp) after the --config file.
#pragma once

#include <string>

#include "inertial/config/daemon_config.hpp"

namespace inertial {

struct DaemonOverrides {
  std::string lcm_url;              ///< DaemonOptions::lcm_url
  std::string channel;              ///< input_channel
  std::string estimate_channel;     ///< estimate_channel
  std::string residual_channel;     ///< residual_channel
  std::string checkpoint;           ///< checkpoint_path
  std::string estimator;            ///< estimator.kind: "gauss_newton", "gradient" or "linear_rls"
  std::string log_level;            ///< log_level: "error", "warn", "info" or "debug"
  std::string publish_rate;         ///< publish_rate_hz [Hz], a positive number
  std::string checkpoint_interval;  ///< checkpoint_interval_s [s], a positive number
  std::string noise_tau;            ///< estimator.measurement_sigma [N m], a positive number
  bool fresh = false;               ///< start_fresh (always applied)
};

/// Applies the given (non-empty) values over *options, and `fresh` always; a throw can leave the
/// options partly changed.
/// @throws std::invalid_argument naming the option ("--publish-rate must be positive", the number
/// parser's "--noise-tau: ..." message, an unknown estimator or log level); *options may then be
/// partly changed.
void ApplyDaemonOverrides(const DaemonOverrides& overrides, DaemonOptions* options);

}  // namespace inertial
