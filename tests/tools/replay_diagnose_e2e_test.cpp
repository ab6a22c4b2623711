// `inertial replay --diagnose --json` end to end: the bundled leg simulated by `inertial simulate`
// with a hidden effect its URDF lacks (Coulomb, viscous, armature, a payload; clean) (links within a CAD model's error, --perturb 0.05; 0.05 N m
// torque noise, the noise the replay is told), written as an lcm-logger log or a candump log of its
// motors, replayed through the online estimator with the online diagnosis. The top suggestion must
// be the hidden effect on the right joint (or link), and on a clean stream nothing is suggested.
#include <gtest/gtest.h>

#include <fstream>

#include <nlohmann/json.hpp>

#include "cli_support.hpp"
#include "simulated_robot.hpp"

namespace inertial {
namespace {

using testing::Describe;
using testing::RunCli;
namespace fs = std::filesystem;

std::string Top(const nlohmann::json& j) {
  const nlohmann::json& s = j.at("suggestions");
  if (s.empty()) return "(none)";
  return s[0].at("effect").get<std::string>() + "@" +
         (s[0].contains("joint") ? s[0]["joint"] : s[0]["link"]).get<std::string>();
}

class ReplayDiagnose : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = testing::UniqueTempPath("replay-diagnose");
    fs::create_directories(dir_);
    leg_ = testing::Example("leg3.urdf");
  }
  void TearDown() override { fs::remove_all(dir_); }

  // Simulates 40 s at 500 Hz with `effects` (empty: none) and replays it with --diagnose --json.
  nlohmann::json Run(const std::string& effects, const std::string& values, bool candump = false) {
    std::vector<std::string> sim = {"simulate", "--model", leg_, "--duration", "40", "--rate", "500", "--perturb", "0.05",
                                    "--noise-tau", "0.05", "--seed", "3"};
    if (!effects.empty()) sim.insert(sim.end(), {"--effects", effects, "--effect-values", values});
    const std::string log = (dir_ / (candump ? "leg.log" : "leg.lcm")).string();
    const std::string motors = (dir_ / "motors.yaml").string();
    if (candump) {
      std::ofstream(motors) << R"(window: 0.002
accel_cutoff_hz: 30
motors:
  - {id: 0x001, joint: abad, protocol: mini_cheetah, position: [-12.5, 12.5], velocity: [-65, 65], torque: [-18, 18]}
  - {id: 0x002, joint: hip, protocol: mini_cheetah, position: [-12.5, 12.5], velocity: [-65, 65], torque: [-18, 18]}
  - {id: 0x003, joint: knee, protocol: mini_cheetah, position: [-12.5, 12.5], velocity: [-65, 65], torque: [-18, 18]}
)";
      sim.insert(sim.end(), {"--write-candump", log, "--can-config", motors});
    } else {
      sim.insert(sim.end(), {"--write-log", log});
    }
    testing::CliRun r = RunCli(sim);
    EXPECT_EQ(r.exit_code, 0) << Describe(r);
    // The online diagnosis as tuned on the Kalman estimator (ekf): with the online fit, the clean
    // candump stream (12-bit velocities, accelerations from a causal filter) biases the masses
    // only the prior holds (the thigh's to 19 kg), and the diagnosis takes that for a payload
    // (issue 36, parts 4 and 7: not done yet).
    std::vector<std::string> replay = {"replay", "--model", leg_, "--estimator", "ekf", "--noise-tau", "0.05", "--diagnose", "--json"};
    if (candump) {
      replay.insert(replay.end(), {"--candump", log, "--can-config", motors});
    } else {
      replay.insert(replay.end(), {"--log", log});
    }
    r = RunCli(replay);
    EXPECT_EQ(r.exit_code, 0) << Describe(r);
    return nlohmann::json::parse(r.out);
  }

  fs::path dir_;
  std::string leg_;
};


// Dry friction on the knee: Coulomb's step, or the asymmetric form that holds it (bp = bn). The
// links, not refitted per candidate online, absorb part of the step unevenly in the two directions,
// so the richer form may win by more than the 2 % the nesting rule asks; both name the right effect
// on the right joint, and the fitted levels must both be near the true 0.1 N m.
void ExpectDryFrictionOnTheKnee(const nlohmann::json& j, double level) {
  const std::string top = Top(j);
  ASSERT_TRUE(top == "coulomb@knee" || top == "asymmetric@knee") << j.dump(1);
  for (const double v : j["suggestions"][0]["values"]) EXPECT_NEAR(v, level, 0.5 * level) << j.dump(1);
}

TEST_F(ReplayDiagnose, CoulombFrictionOnTheKneeFromAnLcmLog) {
  const nlohmann::json j = Run("coulomb@knee", "0.1");
  ExpectDryFrictionOnTheKnee(j, 0.1);
  EXPECT_TRUE(j.contains("unexcited"));
}

TEST_F(ReplayDiagnose, ViscousDampingOnTheHipFromAnLcmLog) {
  const nlohmann::json j = Run("viscous@hip", "0.3");
  EXPECT_EQ(Top(j), "viscous@hip") << j.dump(1);
}

TEST_F(ReplayDiagnose, ArmatureOnTheKneeFromAnLcmLog) {
  const nlohmann::json j = Run("armature@knee", "0.05");
  EXPECT_EQ(Top(j), "armature@knee") << j.dump(1);
}

// A 0.5 kg payload on the foot (fixed to the shank): the shank's estimate departs from its URDF
// beyond the tolerance, and a payload on it takes it back.
TEST_F(ReplayDiagnose, PayloadOnTheShankFromAnLcmLog) {
  const nlohmann::json j = Run("payload@foot:mass=0.5", "0");
  EXPECT_EQ(Top(j), "payload@shank") << j.dump(1);
}

TEST_F(ReplayDiagnose, CoulombFrictionOnTheKneeFromACandumpLog) {
  ExpectDryFrictionOnTheKnee(Run("coulomb@knee", "0.2", /*candump=*/true), 0.2);
}

TEST_F(ReplayDiagnose, CleanStreamsGetNoSuggestion) {
  EXPECT_EQ(Top(Run("", "")), "(none)");
  EXPECT_EQ(Top(Run("", "", /*candump=*/true)), "(none)");
}

}  // namespace
}  // namespace inertial
