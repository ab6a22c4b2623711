// End-to-end tests of `inertial payload`: the built CLI on logs `inertial simulate` writes of the
// bundled 7-DOF arm holding a 2 kg payload on its flange (tool0), against the model and minus a
// baseline run of the same trajectory; the friction a URDF states as <dynamics> fitted; the
// refusals of a link that does not exist (or is fixed to the base) and of a baseline of another
// trajectory.
#include <gtest/gtest.h>

#include <cmath>

#include <nlohmann/json.hpp>

#include "cli_support.hpp"
#include "simulated_robot.hpp"

namespace inertial {
namespace {

using testing::Contains;
using testing::Describe;
using testing::Example;
using testing::RunCli;

// `inertial simulate` of the arm for 8 s at 200 Hz with trajectory seed `seed`; `effects`, their
// --effect-values `values` (empty: simulate's default 0.1) and torque noise `noise` as given.
// Returns the log's path.
std::string Simulate(const std::string& stem, const std::string& effects, const std::string& noise, int seed,
                     const std::string& values = "") {
  const std::string path = testing::UniqueTempPath(stem + ".csv").string();
  std::vector<std::string> args = {"simulate", "--model", Example("arm7.urdf"), "--out", path, "--duration", "8",
                                   "--rate", "200", "--noise-tau", noise, "--seed", std::to_string(seed)};
  if (!effects.empty()) {
    args.push_back("--effects");
    args.push_back(effects);
  }
  if (!values.empty()) {
    args.push_back("--effect-values");
    args.push_back(values);
  }
  const testing::CliRun r = RunCli(args);
  EXPECT_EQ(r.exit_code, 0) << Describe(r);
  return path;
}

TEST(PayloadCli, RefusesALinkThatDoesNotExistNamingTheLinks) {
  // The link is checked before the data are read.
  const std::string data = testing::WriteUniqueTempFile("payload.csv", "t\n0\n");
  const testing::CliRun r = RunCli({"payload", "--model", Example("arm7.urdf"), "--data", data, "--link", "gripper"});
  EXPECT_EQ(r.exit_code, 2) << Describe(r);
  EXPECT_TRUE(r.out.empty()) << r.out;
  EXPECT_TRUE(Contains(r.err, "Error: --link gripper: there is no such link in " + Example("arm7.urdf") +
                                  "; the links a payload can be on: link1, link2, link3, link4, link5, link6, link7, "
                                  "tool0\n"))
      << r.err;
  const testing::CliRun base = RunCli({"payload", "--model", Example("arm7.urdf"), "--data", data, "--link", "base_link"});
  EXPECT_EQ(base.exit_code, 2) << Describe(base);
  EXPECT_TRUE(Contains(base.err, "Error: --link base_link: is fixed to the base of ")) << base.err;
}

// simulate's payload@tool0:mass=2 is its prior shape scaled: a 2 kg sphere of radius 0.05 m at tool0's origin.
TEST(PayloadCli, AgainstTheModelAndFromTheDifference) {
  const std::string with = Simulate("with", "payload@tool0:mass=2", "0.1", 3);
  const std::string baseline = Simulate("baseline", "", "0", 3);
  for (bool difference : {false, true}) {
    std::vector<std::string> args = {"payload", "--model", Example("arm7.urdf"), "--data", with, "--link", "tool0",
                                     "--json"};
    if (difference) {
      args.push_back("--baseline");
      args.push_back(baseline);
    }
    const testing::CliRun r = RunCli(args);
    ASSERT_EQ(r.exit_code, 0) << Describe(r);
    const nlohmann::json j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["link"], "tool0");
    EXPECT_EQ(j["from_difference"].get<bool>(), difference);
    EXPECT_NEAR(j["mass"].get<double>(), 2.0, 0.04) << r.out;
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(j["com"][i].get<double>(), 0.0, 0.005) << r.out;
    EXPECT_TRUE(Contains(j["ur_script"].get<std::string>(), "set_target_payload(")) << r.out;
    EXPECT_TRUE(Contains(j["franka"].get<std::string>(), "robot.setLoad(")) << r.out;
    EXPECT_TRUE(Contains(j["urdf"].get<std::string>(), "<parent link=\"tool0\"/>")) << r.out;
    EXPECT_TRUE(j["held_by_prior"].is_array());
    if (difference) {
      // The same trajectory from the same instant: no shift to speak of, the pairing reported.
      EXPECT_LT(std::abs(j["time_shift"].get<double>()), 1e-4) << r.out;
      EXPECT_LT(j["position_mismatch"].get<double>(), 1e-3) << r.out;
      EXPECT_GE(j["position_mismatch_unshifted"].get<double>(), j["position_mismatch"].get<double>()) << r.out;
      EXPECT_LT(j["mismatch_torque"].get<double>(), 0.1) << r.out;
    }
  }
  const testing::CliRun text = RunCli({"payload", "--model", Example("arm7.urdf"), "--data", with, "--link", "tool0"});
  ASSERT_EQ(text.exit_code, 0) << Describe(text);
  EXPECT_TRUE(Contains(text.out, "Universal Robots (URScript):\n  set_target_payload(")) << text.out;
  EXPECT_TRUE(Contains(text.out, "Franka (libfranka, C++):\n  robot.setLoad(")) << text.out;
}

// Against the model, the friction a URDF states as <dynamics> is part of the model and fitted:
// the residual is the noise.
TEST(PayloadCli, TheModelFilesDynamicsAreFitted) {
  std::string urdf = testing::ReadFile(Example("arm7.urdf"));
  for (size_t at = urdf.find("<limit "); at != std::string::npos; at = urdf.find("<limit ", at + 1)) {
    const size_t end = urdf.find("/>", at) + 2;
    urdf.insert(end, "<dynamics damping=\"0.3\" friction=\"0.3\"/>");
  }
  const std::string model = testing::WriteUniqueTempFile("arm_dynamics.urdf", urdf);
  const std::string with = Simulate("with", "viscous,coulomb,payload@tool0:mass=2", "0.1", 5, "0.3");
  const testing::CliRun r = RunCli({"payload", "--model", model, "--data", with, "--link", "tool0", "--json"});
  ASSERT_EQ(r.exit_code, 0) << Describe(r);
  const nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_LT(j["residual_rms"].get<double>(), 0.12) << r.out;
  EXPECT_NEAR(j["mass"].get<double>(), 2.0, 0.04) << r.out;
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(j["com"][i].get<double>(), 0.0, 0.005) << r.out;
}

TEST(PayloadCli, RefusesABaselineOfAnotherTrajectory) {
  const std::string with = Simulate("with", "payload@tool0:mass=2", "0.1", 3);
  const std::string other = Simulate("other", "", "0", 4);
  const testing::CliRun r = RunCli({"payload", "--model", Example("arm7.urdf"), "--data", with, "--baseline", other,
                                    "--link", "tool0"});
  EXPECT_EQ(r.exit_code, 3) << Describe(r);
  EXPECT_TRUE(Contains(r.err, "do not follow the same trajectory closely enough to be subtracted")) << r.err;
  EXPECT_TRUE(Contains(r.err, "(at most 0.1: ")) << r.err;
  EXPECT_TRUE(Contains(r.err, "% of its range of motion")) << r.err;
  // The position tolerance of the earlier pairing is refused, naming its replacement.
  const testing::CliRun old = RunCli({"payload", "--model", Example("arm7.urdf"), "--data", with, "--baseline", other,
                                      "--link", "tool0", "--max-mismatch", "0.01"});
  EXPECT_EQ(old.exit_code, 2) << Describe(old);
  EXPECT_TRUE(Contains(old.err, "Error: --max-mismatch (a tolerance on the runs' positions) was replaced by "
                                "--max-mismatch-torque")) << old.err;
}

// A baseline recorded 20 ms late (its log starts 4 samples into the motion at 200 Hz) is paired at
// the shift that removes it: the payload as from a baseline that started with the motion.
TEST(PayloadCli, ABaselineRecordedLateIsShifted) {
  const std::string with = Simulate("with", "payload@tool0:mass=2", "0.1", 3);
  const std::string baseline = Simulate("baseline", "", "0", 3);
  std::string text = testing::ReadFile(baseline);
  for (int drop = 0; drop < 4; ++drop) {  // the header stays, the first 4 samples go
    const size_t first = text.find('\n');
    text.erase(first + 1, text.find('\n', first + 1) - first);
  }
  const std::string late = testing::WriteUniqueTempFile("late.csv", text);
  const testing::CliRun r = RunCli({"payload", "--model", Example("arm7.urdf"), "--data", with, "--baseline", late,
                                    "--link", "tool0", "--json"});
  ASSERT_EQ(r.exit_code, 0) << Describe(r);
  const nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_NEAR(j["time_shift"].get<double>(), -0.020, 1e-5) << r.out;
  EXPECT_GT(j["position_mismatch_unshifted"].get<double>(), 0.001) << r.out;
  EXPECT_LT(j["position_mismatch"].get<double>(), 1e-4) << r.out;
  EXPECT_NEAR(j["mass"].get<double>(), 2.0, 0.04) << r.out;
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(j["com"][i].get<double>(), 0.0, 0.005) << r.out;
}

}  // namespace
}  // namespace inertial
