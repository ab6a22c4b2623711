#include "inertial/config/daemon_overrides.hpp"

#include <stdexcept>

#include "inertial/formats/number_parsing.hpp"

namespace inertial {

namespace {

// A positive number, if given.
void ApplyPositive(const std::string& text, const char* option, double* out) {
  if (text.empty()) return;
  *out = ParseDouble(text, option);
  if (!(*out > 0)) throw std::invalid_argument(std::string(option) + " must be positive");
}

}  // namespace

void ApplyDaemonOverrides(const DaemonOverrides& o, DaemonOptions* options) {
  if (!o.lcm_url.empty()) options->lcm_url = o.lcm_url;
  if (!o.channel.empty()) options->input_channel = o.channel;
  if (!o.estimate_channel.empty()) options->estimate_channel = o.estimate_channel;
  if (!o.residual_channel.empty()) options->residual_channel = o.residual_channel;
  if (!o.checkpoint.empty()) options->checkpoint_path = o.checkpoint;
  options->start_fresh = o.fresh;
  if (!o.estimator.empty()) options->estimator.kind = ParseEstimatorKind(o.estimator);
  if (!o.log_level.empty()) options->log_level = ParseLogLevel(o.log_level);
  ApplyPositive(o.publish_rate, "--publish-rate", &options->publish_rate_hz);
  ApplyPositive(o.checkpoint_interval, "--checkpoint-interval", &options->checkpoint_interval_s);
  ApplyPositive(o.noise_tau, "--noise-tau", &options->estimator.measurement_sigma);
}

}  // namespace inertial
