#include "inertial/config/daemon_config.hpp"

#include <cmath>
#include <set>
#include <stdexcept>
#include <string>

#include "inertial/config/message_format.hpp"

namespace inertial {

LogLevel ParseLogLevel(const std::string& name) {
  if (name == "error") return LogLevel::kError;
  if (name == "warn") return LogLevel::kWarn;
  if (name == "info") return LogLevel::kInfo;
  if (name == "debug") return LogLevel::kDebug;
  throw std::invalid_argument("log level '" + name + "' is not one of error, warn, info, debug");
}

void ApplyDaemonConfig(const nlohmann::json& c, DaemonOptions* o) {
  if (!c.is_object()) throw std::invalid_argument("config: expected a JSON object");
  static const std::set<std::string> kKeys{"lcm_url",          "channel",          "estimate_channel", "residual_channel",
                                           "publish_rate_hz",  "residual_window_s", "checkpoint",
                                           "checkpoint_interval_s", "queue_capacity", "estimator",
                                           "measurement_sigma", "log_level",        "format"};
  for (const auto& [key, value] : c.items()) {
    if (kKeys.count(key) == 0) throw std::invalid_argument("config: unknown key \"" + key + "\"");
  }
  auto text = [&](const char* key, std::string* out) {
    if (!c.contains(key)) return;
    if (!c[key].is_string()) throw std::invalid_argument(std::string("config: \"") + key + "\" must be a string");
    *out = c[key].get<std::string>();
  };
  auto positive = [&](const char* key, double* out) {
    if (!c.contains(key)) return;
    if (!c[key].is_number() || !(c[key].get<double>() > 0) || !std::isfinite(c[key].get<double>())) {
      throw std::invalid_argument(std::string("config: \"") + key + "\" must be a positive number");
    }
    *out = c[key].get<double>();
  };
  text("lcm_url", &o->lcm_url);
  text("channel", &o->input_channel);
  text("estimate_channel", &o->estimate_channel);
  text("residual_channel", &o->residual_channel);
  text("checkpoint", &o->checkpoint_path);
  positive("publish_rate_hz", &o->publish_rate_hz);
  positive("residual_window_s", &o->residual_window_s);
  positive("checkpoint_interval_s", &o->checkpoint_interval_s);
  positive("measurement_sigma", &o->estimator.measurement_sigma);
  if (c.contains("queue_capacity")) {
    if (!c["queue_capacity"].is_number_integer() || c["queue_capacity"].get<long long>() < 1 ||
        c["queue_capacity"].get<long long>() > 100000) {
      throw std::invalid_argument("config: \"queue_capacity\" must be an integer in [1, 100000]");
    }
    o->queue_capacity = c["queue_capacity"].get<std::size_t>();
  }
  std::string kind, level;
  text("estimator", &kind);
  if (!kind.empty()) o->estimator.kind = ParseEstimatorKind(kind);
  text("log_level", &level);
  if (!level.empty()) o->log_level = ParseLogLevel(level);
  if (c.contains("format")) o->format = ParseJointMessageFormat(c["format"]);
}

}  // namespace inertial
