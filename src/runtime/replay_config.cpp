#include "inertial/runtime/replay_config.hpp"

#include <stdexcept>

#include "inertial/config/daemon_config_file.hpp"

namespace inertial {

ReplayConfig ReplayConfigFromFile(const std::string& config_path) {
  ReplayConfig config;
  if (config_path.empty()) return config;
  DaemonOptions daemon;
  daemon.input_channel = config.replay.channel;
  try {
    ApplyDaemonConfigFile(config_path, &daemon);
  } catch (const DaemonConfigFileError& e) {
    if (e.reason() == DaemonConfigFileError::Reason::kUnreadable || e.reason() == DaemonConfigFileError::Reason::kTooLarge) {
      throw std::runtime_error(std::string("--config: ") + e.what());
    }
    throw std::runtime_error("--config: " + config_path + ": " + e.what());
  }
  config.replay.channel = daemon.input_channel;
  config.replay.format = daemon.format;
  config.estimator = daemon.estimator;
  config.replay.estimate_period_s = 1.0 / daemon.publish_rate_hz;
  config.replay.residual_window_s = daemon.residual_window_s;
  return config;
}

void ApplyReplayOverrides(const ReplayOverrides& o, ReplayConfig* config) {
  if (o.noise_tau) config->estimator.measurement_sigma = *o.noise_tau;
  if (o.publish_rate_hz) config->replay.estimate_period_s = 1.0 / *o.publish_rate_hz;
  if (o.time_scale) config->replay.csv.time_scale = *o.time_scale;
  if (o.estimator) config->estimator.kind = *o.estimator;
  if (!o.channel.empty()) config->replay.channel = o.channel;
  config->replay.realtime = o.realtime;
  config->replay.csv_path = o.csv_path;
  config->replay.log_path = o.log_path;
}

}  // namespace inertial
