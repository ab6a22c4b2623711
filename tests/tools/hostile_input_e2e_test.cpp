// End-to-end: the inputs a blind fuzzer found breaking the tools (issue 35), each written by the test
// exactly as found, fed to the built programs, and refused with the file error's exit code (5), a
// message saying what is wrong, and within a second (they crashed after 7-13 s, took 10 s and 1.4 GB,
// or were accepted).
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "cli_support.hpp"
#include "simulated_robot.hpp"
#include "test_support.hpp"

namespace inertial {
namespace {

namespace fs = std::filesystem;
using testing::Contains;
using testing::Describe;

struct TimedRun {
  testing::CliRun run;
  double seconds = 0;
};

TimedRun Timed(const std::string& program, const std::vector<std::string>& args) {
  TimedRun t;
  t.seconds = testing::SecondsOf([&] { t.run = testing::RunProgram(program, args); });
  return t;
}

std::string Cli() {
  const char* cli = std::getenv("INERTIAL_CLI");
  return cli != nullptr ? cli : "";
}

std::string Daemon() {
  const char* daemon = std::getenv("INERTIALD");
  return daemon != nullptr ? daemon : "";
}

// The leg's URDF text without its XML declaration.
std::string LegElement() {
  const std::string leg = testing::ReadFile(testing::Example("leg3.urdf"));
  return leg.substr(leg.find("<robot"));
}

void ExpectPromptRefusal(const TimedRun& t, const std::string& message) {
  EXPECT_EQ(t.run.exit_code, 5) << Describe(t.run);
  EXPECT_TRUE(Contains(t.run.err, message)) << Describe(t.run);
  EXPECT_LT(t.seconds, testing::kPromptSeconds) << Describe(t.run);
}

// 1. "<?xml " + 100,000 nested <a> + "?>" + a valid robot: SIGSEGV (exit 139) in urdfdom's TinyXML.
TEST(HostileInput, ElementsInsideABrokenXmlDeclarationAreRefusedByEveryCommandThatLoadsAModel) {
  ASSERT_FALSE(Cli().empty() || Daemon().empty()) << "INERTIAL_CLI and INERTIALD are set by ctest";
  std::string xml = "<?xml ";
  for (int k = 0; k < 100000; ++k) xml += "<a>";
  xml += "?>" + LegElement();
  const std::string path = testing::WriteUniqueTempFile("deep.urdf", xml);
  const std::string message = path + ": is not a valid URDF: the processing instruction at line 1 is not an XML declaration";
  ExpectPromptRefusal(Timed(Cli(), {"check", "--model", path}), message);
  ExpectPromptRefusal(Timed(Cli(), {"validate", "--model", path, "--data", "/nonexistent/run.csv"}), message);
  ExpectPromptRefusal(Timed(Daemon(), {"--model", path, "--lcm-url", "memq://"}), message);
  fs::remove(path);
}

// 2. A checkpoint whose version is 1e308: undefined behaviour, then "version -2147483648", exit 1.
TEST(HostileInput, ACheckpointVersionThatIsNoIntegerIsAFileError) {
  ASSERT_FALSE(Daemon().empty());
  for (const auto& [version, shown] : std::vector<std::pair<std::string, std::string>>{{"1e308", "1e+308"}, {"1.9", "1.9"}}) {
    const std::string path = testing::WriteUniqueTempFile(
        "state.json", "{\"format\": \"inertial-estimator-state\", \"version\": " + version + "}");
    const std::string before = testing::ReadFile(path);
    ExpectPromptRefusal(Timed(Daemon(), {"--model", testing::Example("leg3.urdf"), "--checkpoint", path, "--lcm-url", "memq://"}),
                        "\"version\" is " + shown + ", not an integer from 1 to 1000000");
    EXPECT_EQ(testing::ReadFile(path), before) << "the checkpoint is left untouched";
    fs::remove(path);
  }
}

// 3. motors.yaml with one value of 1.5 million commas: 9.9 s and 1.4 GB inside yaml-cpp.
TEST(HostileInput, AMotorsYamlOverTheSettingsLimitIsRefusedBeforeParsing) {
  ASSERT_FALSE(Cli().empty() || Daemon().empty());
  const std::string text = "motors:\n  - id: 0x141\n    joint: knee\n    protocol: linear\n    position: {byte: 0, width: 2, scale: " +
                           std::string(1500000, ',') + "0.001}\n";
  const std::string path = testing::WriteUniqueTempFile("motors.yaml", text);
  const std::string candump = testing::WriteUniqueTempFile("frames.log", "(0.000000) can0 141#0000000000000000\n");
  const std::string message = path + ": the motor configuration is " + std::to_string(text.size()) + " bytes, over its limit of 64 KiB";
  ExpectPromptRefusal(Timed(Cli(), {"replay", "--model", testing::Example("leg3.urdf"), "--candump", candump, "--can-config", path}),
                      message);
  ExpectPromptRefusal(
      Timed(Daemon(), {"--model", testing::Example("leg3.urdf"), "--can", "vcan0", "--can-config", path, "--lcm-url", "memq://"}),
      message);
  fs::remove(path);
  fs::remove(candump);
}

// 4. A joint 1e300 m from its parent passed `check` (exit 0). (Line 5: the leg's text from <robot> on.)
TEST(HostileInput, ALengthBeyondAnyRobotIsRefusedByCheck) {
  ASSERT_FALSE(Cli().empty());
  std::string xml = LegElement();
  const std::size_t origin = xml.find("<origin xyz=\"", xml.find("<joint"));
  ASSERT_NE(origin, std::string::npos);
  const std::size_t value = origin + std::string("<origin xyz=\"").size();
  xml.replace(value, xml.find('"', value) - value, "0 0 1e300");
  const std::string path = testing::WriteUniqueTempFile("far.urdf", xml);
  ExpectPromptRefusal(Timed(Cli(), {"check", "--model", path}),
                      "joint 'abad': <origin> (line 5): attribute 'xyz' holds 1e+300 m, beyond the 1000 m of any robot");
  fs::remove(path);
}

}  // namespace
}  // namespace inertial
