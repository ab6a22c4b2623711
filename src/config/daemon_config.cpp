#include "inertial/config/daemon_config.hpp"

#include <cmath>
#include <limits>
#include <set>
#include <stdexcept>
#include <string>

#include "inertial/config/message_format.hpp"
#include "inertial/formats/json_integer.hpp"

namespace inertial {

LogLevel ParseLogLevel(const std::string& name) {
  if (name == "error") return LogLevel::kError;
  if (name == "warn") return LogLevel::kWarn;
  if (name == "info") return LogLevel::kInfo;
  if (name == "debug") return LogLevel::kDebug;
  throw std::invalid_argument("log level '" + name + "' is not one of error, warn, info, debug");
}

namespace {

// The "tuning" object (daemon_config.hpp lists the keys, units, defaults and ranges).
void ApplyTuning(const nlohmann::json& t, OnlineEstimatorOptions* e) {
  if (!t.is_object()) throw std::invalid_argument("config: \"tuning\" must be an object");
  static const std::set<std::string> kKeys{"theta_std", "effect_std", "forgetting", "process_noise",
                                           "max_variance_factor", "huber", "gate", "max_consecutive_outliers",
                                           "max_step", "gain"};
  for (const auto& [key, value] : t.items()) {
    if (kKeys.count(key) == 0) throw std::invalid_argument("config: tuning: unknown key \"" + key + "\"");
  }
  // A number in the range (lo, hi) or [lo, hi], as `closed_lo` and `closed_hi` say.
  auto number = [&](const char* key, double lo, bool closed_lo, double hi, bool closed_hi, const char* range,
                    auto&& apply) {
    if (!t.contains(key)) return;
    const nlohmann::json& v = t[key];
    const double x = v.is_number() ? v.get<double>() : std::nan("");
    const bool ok = std::isfinite(x) && (closed_lo ? x >= lo : x > lo) && (closed_hi ? x <= hi : x < hi);
    if (!ok) throw std::invalid_argument(std::string("config: tuning: \"") + key + "\" must be a number " + range);
    apply(x);
  };
  const double inf = std::numeric_limits<double>::infinity();
  number("theta_std", 0, false, inf, false, "> 0", [&](double x) { e->theta_std = x; });
  number("effect_std", 0, false, inf, false, "> 0", [&](double x) { e->effect_std = x; });
  number("forgetting", 0, false, 1, true, "in (0, 1]", [&](double x) { e->kalman.forgetting = x; });
  number("process_noise", 0, true, inf, false, ">= 0", [&](double x) { e->kalman.process_noise = x; });
  number("max_variance_factor", 1, true, inf, false, ">= 1", [&](double x) { e->kalman.max_variance_factor = x; });
  number("huber", 0, false, inf, false, "> 0", [&](double x) { e->kalman.huber = e->gradient.huber = x; });
  number("gate", 0, false, inf, false, "> 0", [&](double x) { e->kalman.gate = e->gradient.gate = x; });
  number("max_step", 0, false, inf, false, "> 0", [&](double x) { e->kalman.max_step = e->gradient.max_step = x; });
  number("gain", 0, false, 2, false, "in (0, 2)", [&](double x) { e->gradient.gain = x; });
  if (t.contains("max_consecutive_outliers")) {
    const nlohmann::json& v = t["max_consecutive_outliers"];
    const std::optional<std::int64_t> n = JsonInteger(v, 1, 1000000000);
    if (!n) throw std::invalid_argument("config: tuning: \"max_consecutive_outliers\" " + NotAnIntegerText(v, 1, 1000000000));
    e->kalman.max_consecutive_outliers = e->gradient.max_consecutive_outliers = static_cast<int>(*n);
  }
  if (!(e->kalman.gate > e->kalman.huber)) {
    throw std::invalid_argument("config: tuning: \"gate\" must exceed \"huber\" (outliers lie beyond the down-weighted band)");
  }
}

}  // namespace

void ApplyDaemonConfig(const nlohmann::json& c, DaemonOptions* o) {
  if (!c.is_object()) throw std::invalid_argument("config: expected a JSON object");
  static const std::set<std::string> kKeys{"lcm_url",          "channel",          "estimate_channel", "residual_channel",
                                           "publish_rate_hz",  "residual_window_s", "checkpoint",
                                           "checkpoint_interval_s", "queue_capacity", "estimator",
                                           "noise_tau",        "log_level",        "format",
                                           "tuning",           "diagnosis_channel", "diagnosis_period_s",
                                           "payload_channel"};
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
  text("diagnosis_channel", &o->diagnosis_channel);
  text("payload_channel", &o->payload_channel);
  text("checkpoint", &o->checkpoint_path);
  positive("diagnosis_period_s", &o->diagnosis_period_s);
  positive("publish_rate_hz", &o->publish_rate_hz);
  positive("residual_window_s", &o->residual_window_s);
  positive("checkpoint_interval_s", &o->checkpoint_interval_s);
  positive("noise_tau", &o->estimator.measurement_sigma);
  if (c.contains("queue_capacity")) {
    const std::optional<std::int64_t> n = JsonInteger(c["queue_capacity"], 1, 100000);
    if (!n) throw std::invalid_argument("config: \"queue_capacity\" " + NotAnIntegerText(c["queue_capacity"], 1, 100000));
    o->queue_capacity = static_cast<std::size_t>(*n);
  }
  std::string kind, level;
  text("estimator", &kind);
  if (!kind.empty()) o->estimator.kind = ParseEstimatorKind(kind);
  text("log_level", &level);
  if (!level.empty()) o->log_level = ParseLogLevel(level);
  if (c.contains("format")) o->format = ParseJointMessageFormat(c["format"]);
  if (c.contains("tuning")) ApplyTuning(c["tuning"], &o->estimator);
}

}  // namespace inertial
