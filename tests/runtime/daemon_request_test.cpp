// inertiald's request: options that do not go together, files that cannot be used and outputs
// that would overwrite inputs are refused in a fixed order, each with its kind and message; the
// settings come from the defaults, the configuration and the command line, in that order; the
// daemon it makes starts from the prior (a body) or the URDF (a robot) and writes its model file.
#include "inertial/runtime/daemon_request.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "cli_support.hpp"
#include "inertial/formats/model_file.hpp"
#include "simulated_robot.hpp"

namespace inertial {
namespace {

struct Refusal {
  StartFailure failure = StartFailure::kCannotStart;
  std::string message;
};

Refusal RefusalOf(const DaemonRequest& r, bool make = false) {
  try {
    if (make) {
      MakeDaemon(r, nullptr);
    } else {
      DaemonOptionsFor(r);
    }
  } catch (const DaemonStartError& e) {
    return {e.failure(), e.what()};
  }
  ADD_FAILURE() << "the request was accepted";
  return {};
}

DaemonRequest Body() {
  DaemonRequest r;
  r.body = true;
  r.overrides.lcm_url = "memq://";
  r.overrides.log_level = "error";
  return r;
}

TEST(DaemonRequest, OptionsThatDoNotGoTogetherAreUsageErrors) {
  DaemonRequest r;
  Refusal e = RefusalOf(r);
  EXPECT_EQ(e.failure, StartFailure::kUsage);
  EXPECT_EQ(e.message, "give --model URDF (a robot) or --body (a single body), not neither");
  r = Body();
  r.model_path = "robot.urdf";
  EXPECT_EQ(RefusalOf(r).message, "give --model URDF (a robot) or --body (a single body), not both");
  r = Body();
  r.write_urdf = "out.urdf";
  EXPECT_EQ(RefusalOf(r).message,
            "--write-urdf needs --model (a single body has no URDF; its estimate is in estimate_t)");
  r = Body();
  r.can_interface = "can0";
  r.can_config = "motors.yaml";
  EXPECT_EQ(RefusalOf(r).message, "--can and --can-config go together, with --model");
  r = DaemonRequest{};
  r.model_path = "robot.urdf";
  r.can_interface = "can0";
  e = RefusalOf(r);
  EXPECT_EQ(e.failure, StartFailure::kUsage);
  EXPECT_EQ(e.message, "--can and --can-config go together, with --model");
}

TEST(DaemonRequest, AConfigurationThatCannotBeUsedIsAFileError) {
  DaemonRequest r = Body();
  r.config_path = testing::UniqueTempPath("absent.json").string();
  Refusal e = RefusalOf(r);
  EXPECT_EQ(e.failure, StartFailure::kFileError);
  EXPECT_EQ(e.message, "--config: cannot read the configuration '" + r.config_path + "': No such file or directory");
  r.config_path = testing::WriteUniqueTempFile("broken.json", "{");
  e = RefusalOf(r);
  EXPECT_EQ(e.failure, StartFailure::kFileError);
  EXPECT_EQ(e.message.rfind("--config: " + r.config_path + " is not valid JSON: [json.exception.parse_error", 0), 0u)
      << e.message;
  std::filesystem::remove(r.config_path);
  r.config_path = testing::WriteUniqueTempFile("invalid.json", R"({"publish_rate": 5})");
  e = RefusalOf(r);
  EXPECT_EQ(e.failure, StartFailure::kFileError);
  EXPECT_EQ(e.message, "--config " + r.config_path + ": config: unknown key \"publish_rate\"");
  std::filesystem::remove(r.config_path);
}

TEST(DaemonRequest, TheCommandLineOverridesTheConfigurationWhichOverridesTheDefaults) {
  DaemonRequest r = Body();
  EXPECT_EQ(DaemonOptionsFor(r).input_channel, "INERTIAL_BODY_WRENCH");
  r.config_path = testing::WriteUniqueTempFile("config.json", R"({"publish_rate_hz": 20, "checkpoint_interval_s": 7, "channel": "C"})");
  DaemonOptions o = DaemonOptionsFor(r);
  EXPECT_EQ(o.input_channel, "C");
  EXPECT_EQ(o.publish_rate_hz, 20.0);
  EXPECT_EQ(o.checkpoint_interval_s, 7.0);
  r.overrides.publish_rate = "5";
  r.overrides.channel = "D";
  o = DaemonOptionsFor(r);
  EXPECT_EQ(o.input_channel, "D");
  EXPECT_EQ(o.publish_rate_hz, 5.0);
  EXPECT_EQ(o.checkpoint_interval_s, 7.0);
  EXPECT_EQ(o.lcm_url, "memq://");
  r.overrides.publish_rate = "-1";
  const Refusal e = RefusalOf(r);
  EXPECT_EQ(e.failure, StartFailure::kUsage);
  EXPECT_EQ(e.message, "--publish-rate must be positive");
  std::filesystem::remove(r.config_path);
}

TEST(DaemonRequest, OutputsMayNotNameAnInputNorEachOther) {
  DaemonRequest r;
  r.model_path = testing::Example("leg3.urdf");
  r.overrides.checkpoint = r.model_path;
  Refusal e = RefusalOf(r);
  EXPECT_EQ(e.failure, StartFailure::kUsage);
  EXPECT_EQ(e.message, "--checkpoint '" + r.model_path + "' is the --model input: refusing to overwrite an input (choose another output path)");
  r.overrides.checkpoint.clear();
  // The configuration's checkpoint counts, and two spellings of one new file are the same file.
  const std::filesystem::path dir = testing::UniqueTempPath("outputs");
  std::filesystem::create_directories(dir / "sub");
  r.config_path = testing::WriteUniqueTempFile("config.json", "{\"checkpoint\": \"" + (dir / "estimate.out").string() + "\"}");
  r.write_urdf = (dir / "sub" / ".." / "estimate.out").string();
  e = RefusalOf(r);
  EXPECT_EQ(e.failure, StartFailure::kUsage);
  EXPECT_EQ(e.message, "--checkpoint and --write-urdf name the same file '" + (dir / "estimate.out").string() + "'");
  r.write_urdf = r.config_path;
  EXPECT_EQ(RefusalOf(r).message,
            "--write-urdf '" + r.config_path + "' is the --config input: refusing to overwrite an input (choose another output path)");
  std::filesystem::remove(r.config_path);
  std::filesystem::remove_all(dir);
}

TEST(DaemonRequest, ABodyStartsFromItsPrior) {
  DaemonRequest r = Body();
  r.prior = "2 0.2 0.4 -0.6 1 1 1 0 0 0";
  const std::unique_ptr<EstimationDaemon> daemon = MakeDaemon(r, nullptr);
  ASSERT_NE(daemon->body_estimator(), nullptr);
  EXPECT_EQ(daemon->robot_estimator(), nullptr);
  const InertialParams b = daemon->body_estimator()->Body();
  EXPECT_NEAR(b.mass(), 2.0, 1e-12);
  EXPECT_NEAR(b.com().x(), 0.1, 1e-12);  // h / m
  EXPECT_NEAR(b.com().y(), 0.2, 1e-12);
  EXPECT_NEAR(b.com().z(), -0.3, 1e-12);
  r.prior = "1 0 0";
  const Refusal e = RefusalOf(r, true);
  EXPECT_EQ(e.failure, StartFailure::kUsage);
  EXPECT_EQ(e.message, "--prior: 3 numbers given, 10 expected ('1 0 0')");
}

TEST(DaemonRequest, ModelsAndMotorsThatCannotBeUsedAreFileErrors) {
  DaemonRequest r;
  r.model_path = testing::UniqueTempPath("absent.urdf").string();
  r.overrides.lcm_url = "memq://";
  Refusal e = RefusalOf(r, true);
  EXPECT_EQ(e.failure, StartFailure::kFileError);
  EXPECT_EQ(e.message, "cannot read the URDF '" + r.model_path + "': No such file or directory");
  r.model_path = testing::Example("leg3.urdf");
  r.can_interface = "inertial_no_such_can";
  r.can_config = testing::UniqueTempPath("absent.yaml").string();
  e = RefusalOf(r, true);
  EXPECT_EQ(e.failure, StartFailure::kFileError);
  EXPECT_EQ(e.message.rfind("--can-config: ", 0), 0u) << e.message;
  r.can_interface.clear();
  r.can_config.clear();
  r.effects = "no_such_effect@knee";
  EXPECT_EQ(RefusalOf(r, true).failure, StartFailure::kUsage);
}

TEST(DaemonRequest, ARobotWritesItsEstimateAsAModelFileAtExit) {
  DaemonRequest r;
  r.model_path = testing::Example("leg3.urdf");
  r.write_urdf = testing::UniqueTempPath("estimate.urdf").string();
  r.overrides.lcm_url = "memq://";
  r.overrides.log_level = "error";
  std::atomic<bool> write_request{false};
  const std::unique_ptr<EstimationDaemon> daemon = MakeDaemon(r, &write_request);
  ASSERT_NE(daemon->robot_estimator(), nullptr);
  const std::atomic<bool> stop{true};
  EXPECT_EQ(daemon->Run(stop), 0);
  const std::string text = testing::ReadFile(r.write_urdf);
  EXPECT_NE(text.find("the online estimate of inertiald (0 samples)"), std::string::npos) << text;
  // No sample: the estimate is the URDF's, the foot (0.06 kg) merged into the shank (0.45 kg).
  const RobotModel written = LoadUrdf(r.write_urdf);
  const RobotDynamics model = MakeRobotDynamics(written, {});
  ASSERT_EQ(model.bodies().size(), 3u);
  EXPECT_NEAR(model.bodies()[0].prior.mass(), 2.0, 1e-9);
  EXPECT_NEAR(model.bodies()[1].prior.mass(), 1.8, 1e-9);
  EXPECT_NEAR(model.bodies()[2].prior.mass(), 0.51, 1e-9);
  std::filesystem::remove(r.write_urdf);
}

}  // namespace
}  // namespace inertial
