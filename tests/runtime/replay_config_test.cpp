// How `inertial replay` is set up: the defaults, inertiald's configuration over them (its channel,
// publish rate as a period, residual window, estimator and noise), the command line over that.
#include "inertial/runtime/replay_config.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "cli_support.hpp"

namespace inertial {
namespace {

std::string ErrorOf(const std::string& path) {
  try {
    ReplayConfigFromFile(path);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

TEST(ReplayConfig, WithoutAConfigurationTheDefaults) {
  const ReplayConfig c = ReplayConfigFromFile("");
  EXPECT_EQ(c.replay.channel, "INERTIAL_JOINT_STATE");
  EXPECT_EQ(c.replay.estimate_period_s, 0.1);
  EXPECT_EQ(c.replay.residual_window_s, 1.0);
  EXPECT_EQ(c.estimator.measurement_sigma, 1.0);
  EXPECT_EQ(c.estimator.kind, EstimatorKind::kGaussNewton);
  EXPECT_FALSE(c.replay.can.has_value());
}

TEST(ReplayConfig, TheDaemonsConfigurationSetsTheReplay) {
  const std::string path = testing::WriteUniqueTempFile("config.json", R"({"channel": "ARM", "publish_rate_hz": 20, "residual_window_s": 2.5,
      "noise_tau": 0.3, "estimator": "linear_rls", "estimate_channel": "NOT_USED"})");
  const ReplayConfig c = ReplayConfigFromFile(path);
  EXPECT_EQ(c.replay.channel, "ARM");
  EXPECT_DOUBLE_EQ(c.replay.estimate_period_s, 0.05);  // 1 / 20 Hz
  EXPECT_EQ(c.replay.residual_window_s, 2.5);
  EXPECT_EQ(c.estimator.measurement_sigma, 0.3);
  EXPECT_EQ(c.estimator.kind, EstimatorKind::kLinearRls);
  EXPECT_EQ(c.replay.estimate_channel, "INERTIAL_ESTIMATE");
  std::filesystem::remove(path);
  const std::string no_channel = testing::WriteUniqueTempFile("config.json", R"({"publish_rate_hz": 4})");
  EXPECT_EQ(ReplayConfigFromFile(no_channel).replay.channel, "INERTIAL_JOINT_STATE");
  EXPECT_DOUBLE_EQ(ReplayConfigFromFile(no_channel).replay.estimate_period_s, 0.25);
  std::filesystem::remove(no_channel);
}

TEST(ReplayConfig, AConfigurationThatCannotBeUsedSaysWhy) {
  const std::string absent = testing::UniqueTempPath("absent.json").string();
  EXPECT_EQ(ErrorOf(absent), "--config: cannot read the configuration '" + absent + "': No such file or directory");
  const std::string invalid = testing::WriteUniqueTempFile("config.json", R"({"noise_tau": "loud"})");
  EXPECT_EQ(ErrorOf(invalid).rfind("--config: " + invalid + ": config: ", 0), 0u) << ErrorOf(invalid);
  const std::string broken = testing::WriteUniqueTempFile("config.json", "not json");
  EXPECT_EQ(ErrorOf(broken).rfind("--config: " + broken + ": [json.exception.parse_error", 0), 0u) << ErrorOf(broken);
  std::filesystem::remove(invalid);
  std::filesystem::remove(broken);
}

TEST(ReplayConfig, TheCommandLineOverridesTheConfiguration) {
  const std::string path = testing::WriteUniqueTempFile("config.json", R"({"channel": "ARM", "publish_rate_hz": 20, "noise_tau": 0.3})");
  ReplayConfig c = ReplayConfigFromFile(path);
  ReplayOverrides o;
  o.realtime = true;
  o.csv_path = "estimates.csv";
  o.log_path = "estimates.lcm";
  ApplyReplayOverrides(o, &c);  // nothing numeric given: the configuration's values stay
  EXPECT_EQ(c.replay.channel, "ARM");
  EXPECT_DOUBLE_EQ(c.replay.estimate_period_s, 0.05);
  EXPECT_EQ(c.estimator.measurement_sigma, 0.3);
  EXPECT_EQ(c.replay.csv.time_scale, 0.0);  // not given: stamps must look like seconds
  EXPECT_TRUE(c.replay.realtime);
  EXPECT_EQ(c.replay.csv_path, "estimates.csv");
  EXPECT_EQ(c.replay.log_path, "estimates.lcm");
  o.noise_tau = 0.7;
  o.publish_rate_hz = 8.0;
  o.time_scale = 1e-3;
  o.estimator = EstimatorKind::kGradient;
  o.channel = "LEG";
  ApplyReplayOverrides(o, &c);
  EXPECT_EQ(c.replay.channel, "LEG");
  EXPECT_EQ(c.replay.estimate_period_s, 0.125);
  EXPECT_EQ(c.estimator.measurement_sigma, 0.7);
  EXPECT_EQ(c.replay.csv.time_scale, 1e-3);
  EXPECT_EQ(c.estimator.kind, EstimatorKind::kGradient);
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace inertial
