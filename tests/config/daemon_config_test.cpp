#include "inertial/config/daemon_config.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace inertial {
namespace {

std::string ErrorOf(const std::string& text) {
  DaemonOptions o;
  try {
    ApplyDaemonConfig(nlohmann::json::parse(text), &o);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(DaemonConfig, TuningReachesTheEstimatorsAndAbsentKeysKeepTheDefaults) {
  DaemonOptions o;
  const OnlineEstimatorOptions defaults = o.estimator;
  ApplyDaemonConfig(nlohmann::json::parse(R"({"noise_tau": 0.2, "tuning": {"forgetting": 0.995, "process_noise": 1e-9,
      "max_variance_factor": 4, "huber": 2.5, "gate": 12, "max_consecutive_outliers": 7, "max_step": 0.2,
      "gain": 0.1, "theta_std": 0.5, "effect_std": 2}})"),
                    &o);
  EXPECT_EQ(o.estimator.measurement_sigma, 0.2);
  EXPECT_EQ(o.estimator.kalman.forgetting, 0.995);
  EXPECT_EQ(o.estimator.kalman.process_noise, 1e-9);
  EXPECT_EQ(o.estimator.kalman.max_variance_factor, 4.0);
  EXPECT_EQ(o.estimator.kalman.huber, 2.5);
  EXPECT_EQ(o.estimator.gradient.huber, 2.5);
  EXPECT_EQ(o.estimator.kalman.gate, 12.0);
  EXPECT_EQ(o.estimator.gradient.gate, 12.0);
  EXPECT_EQ(o.estimator.kalman.max_consecutive_outliers, 7);
  EXPECT_EQ(o.estimator.gradient.max_consecutive_outliers, 7);
  EXPECT_EQ(o.estimator.kalman.max_step, 0.2);
  EXPECT_EQ(o.estimator.gradient.gain, 0.1);
  EXPECT_EQ(o.estimator.theta_std, 0.5);
  EXPECT_EQ(o.estimator.effect_std, 2.0);

  DaemonOptions partial;
  ApplyDaemonConfig(nlohmann::json::parse(R"({"tuning": {"forgetting": 0.99}})"), &partial);
  EXPECT_EQ(partial.estimator.kalman.forgetting, 0.99);
  EXPECT_EQ(partial.estimator.kalman.huber, defaults.kalman.huber);
  EXPECT_EQ(partial.estimator.gradient.max_step, defaults.gradient.max_step);
  EXPECT_EQ(partial.estimator.measurement_sigma, defaults.measurement_sigma);
}

// The online diagnosis's and the payload events' channels and period: defaults on, "" turns them off.
TEST(DaemonConfig, DiagnosisAndPayloadChannels) {
  DaemonOptions o;
  EXPECT_EQ(o.diagnosis_channel, "INERTIAL_DIAGNOSIS");
  EXPECT_EQ(o.payload_channel, "INERTIAL_PAYLOAD_EVENT");
  EXPECT_EQ(o.diagnosis_period_s, 5.0);
  ApplyDaemonConfig(nlohmann::json::parse(R"({"diagnosis_channel": "LEG_DIAGNOSIS", "diagnosis_period_s": 2.5,
      "payload_channel": ""})"),
                    &o);
  EXPECT_EQ(o.diagnosis_channel, "LEG_DIAGNOSIS");
  EXPECT_EQ(o.diagnosis_period_s, 2.5);
  EXPECT_EQ(o.payload_channel, "");
  EXPECT_NE(ErrorOf(R"({"diagnosis_period_s": 0})").find("\"diagnosis_period_s\" must be a positive number"),
            std::string::npos);
  EXPECT_NE(ErrorOf(R"({"diagnosis_channel": 3})").find("\"diagnosis_channel\" must be a string"), std::string::npos);
}

// Issue 35: integers are checked as integers in range before any conversion (1e308 in an int is
// undefined behaviour; 1.9 was truncated).
TEST(DaemonConfig, IntegersAreCheckedBeforeConversion) {
  // Each as written, and as nlohmann writes it back.
  for (const auto& [bad, shown] : std::vector<std::pair<std::string, std::string>>{
           {"1e308", "1e+308"}, {"1.9", "1.9"}, {"0", "0"}, {"100001", "100001"}, {"-5", "-5"},
           {"18446744073709551615", "18446744073709551615"}, {"\"10\"", "\"10\""}, {"null", "null"}}) {
    EXPECT_EQ(ErrorOf(R"({"queue_capacity": )" + bad + "}"), "config: \"queue_capacity\" is " + shown + ", not an integer from 1 to 100000");
  }
  for (const auto& [bad, shown] : std::vector<std::pair<std::string, std::string>>{{"1e308", "1e+308"}, {"-1e308", "-1e+308"}, {"0.5", "0.5"}}) {
    EXPECT_EQ(ErrorOf(R"({"tuning": {"max_consecutive_outliers": )" + bad + "}}"),
              "config: tuning: \"max_consecutive_outliers\" is " + shown + ", not an integer from 1 to 1000000000");
  }
  DaemonOptions o;
  ApplyDaemonConfig(nlohmann::json::parse(R"({"queue_capacity": 512.0, "tuning": {"max_consecutive_outliers": 7}})"), &o);
  EXPECT_EQ(o.queue_capacity, 512u);
  EXPECT_EQ(o.estimator.kalman.max_consecutive_outliers, 7);
  EXPECT_EQ(o.estimator.gradient.max_consecutive_outliers, 7);
}

TEST(DaemonConfig, OutOfRangeTuningIsRefusedNamingTheKeyAndItsRange) {
  EXPECT_EQ(ErrorOf(R"({"tuning": {"forgetting": 0}})"), "config: tuning: \"forgetting\" must be a number in (0, 1]");
  EXPECT_EQ(ErrorOf(R"({"tuning": {"forgetting": 1.5}})"), "config: tuning: \"forgetting\" must be a number in (0, 1]");
  EXPECT_EQ(ErrorOf(R"({"tuning": {"process_noise": -1}})"), "config: tuning: \"process_noise\" must be a number >= 0");
  EXPECT_EQ(ErrorOf(R"({"tuning": {"max_variance_factor": 0.5}})"),
            "config: tuning: \"max_variance_factor\" must be a number >= 1");
  EXPECT_EQ(ErrorOf(R"({"tuning": {"gain": 2}})"), "config: tuning: \"gain\" must be a number in (0, 2)");
  EXPECT_EQ(ErrorOf(R"({"tuning": {"huber": "3"}})"), "config: tuning: \"huber\" must be a number > 0");
  EXPECT_EQ(ErrorOf(R"({"tuning": {"max_consecutive_outliers": 2.5}})"),
            "config: tuning: \"max_consecutive_outliers\" is 2.5, not an integer from 1 to 1000000000");
  EXPECT_EQ(ErrorOf(R"({"tuning": {"huber": 40}})"),
            "config: tuning: \"gate\" must exceed \"huber\" (outliers lie beyond the down-weighted band)");
  EXPECT_EQ(ErrorOf(R"({"tuning": {"forgeting": 0.9}})"), "config: tuning: unknown key \"forgeting\"");
  EXPECT_EQ(ErrorOf(R"({"tuning": 3})"), "config: \"tuning\" must be an object");
  EXPECT_EQ(ErrorOf(R"({"measurement_sigma": 1})"), "config: unknown key \"measurement_sigma\"");
  EXPECT_EQ(ErrorOf(R"({"noise_tau": -1})"), "config: \"noise_tau\" must be a positive number");
}

}  // namespace
}  // namespace inertial
