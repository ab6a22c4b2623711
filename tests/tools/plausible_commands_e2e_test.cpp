// End-to-end tests of issue 45 part 1 in the commands: plausibility in `validate` and `check`,
// regions given by the user (--region) and the robot's weighed mass (--total-mass) in the commands
// that fit. The data: the bundled leg carrying 2 kg at its foot that its URDF does not have (the fit
// gives the shank about five times its 0.51 kg), and the bundled arm with a 196 kg upper arm.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "cli_support.hpp"
#include "inertial/formats/joint_csv.hpp"
#include "inertial/formats/model_file.hpp"
#include "formats/urdf_text.hpp"
#include "simulated_robot.hpp"

namespace inertial {
namespace {

using testing::Contains;
using testing::Describe;
using testing::RunCli;
namespace fs = std::filesystem;

const std::string& Leg() {
  static const std::string leg = testing::Example("leg3.urdf");
  return leg;
}

// A temporary file removed when the test program ends.
struct TempFile {
  fs::path path;
  ~TempFile() {
    std::error_code ec;
    fs::remove(path, ec);
  }
};

// 10 s at 200 Hz of the leg (URDF links, 4.31 kg) carrying a 2 kg payload at its foot, 0.05 N m of
// torque noise, written to a new file.
fs::path WriteLoadedLegLog() {
  const RobotModel robot = LoadUrdf(Leg());
  const RobotDynamics loaded = MakeRobotDynamics(robot, ParseEffectList("payload@foot:mass=2"));
  const testing::SimulatedLogs logs =
      testing::SimulateLogs(loaded, Eigen::VectorXd::Zero(loaded.num_parameters()), 0.05, 10.0, 41, 200);
  const fs::path path = testing::UniqueTempPath("loaded_leg.csv");
  WriteJointCsv(path.string(), logs.train);
  return path;
}

// That log, written once per test program and removed when it ends.
const fs::path& LoadedLegLog() {
  static const TempFile file{WriteLoadedLegLog()};
  return file.path;
}

nlohmann::json Json(const testing::CliRun& r) {
  EXPECT_EQ(r.exit_code, 0) << Describe(r);
  try {
    return nlohmann::json::parse(r.out);
  } catch (const std::exception& e) {
    ADD_FAILURE() << "not JSON: " << e.what() << "\n" << Describe(r);
    return {};
  }
}

double LinkMasses(const nlohmann::json& identify) {
  double total = 0.0;
  for (const auto& b : identify["bodies"]) total += b["mass"].get<double>();
  return total;
}

// The weighed leg (4.5 kg) as a bound: without it the fit's links weigh about 6.3 kg (the payload
// spent on the shank); with it they stay at or below 4.5 kg, reported against it.
TEST(PlausibleCommands, IdentifyKeepsTheLinksWithinTheWeighedMass) {
  const nlohmann::json free = Json(RunCli({"identify", "--model", Leg(), "--data", LoadedLegLog().string(), "--json"}));
  const testing::CliRun bounded_run =
      RunCli({"identify", "--model", Leg(), "--data", LoadedLegLog().string(), "--total-mass", "4.5", "--json"});
  const nlohmann::json bounded = Json(bounded_run);
  EXPECT_GT(LinkMasses(free), 4.5 + 1.0);
  EXPECT_FALSE(free.contains("total_mass"));
  EXPECT_LE(LinkMasses(bounded), 4.5);
  ASSERT_TRUE(bounded.contains("total_mass")) << bounded_run.out;
  EXPECT_TRUE(bounded["total_mass"]["within"].get<bool>());
  EXPECT_NEAR(bounded["total_mass"]["links"].get<double>(), LinkMasses(bounded), 1e-9);
  EXPECT_EQ(bounded["total_mass"]["fixed"].get<double>(), 0.0);  // the leg's base is massless
  EXPECT_TRUE(Contains(bounded_run.err, "note: --total-mass 4.5 kg: the links' masses plus 0 kg fixed to the base "
                                        "(none) are kept at most it; the URDF's links weigh 4.31 kg"))
      << bounded_run.err;
  std::cout << "links: free " << LinkMasses(free) << " kg, bounded " << LinkMasses(bounded) << " kg\n";
  const testing::CliRun text =
      RunCli({"identify", "--model", Leg(), "--data", LoadedLegLog().string(), "--total-mass", "4.5"});
  EXPECT_TRUE(Contains(text.out, "Total mass: ") && Contains(text.out, " kg of links against the robot's 4.5 kg as "
                                                                      "weighed (--total-mass): within it"))
      << text.out;
}

// A bound far above the links' total: the barrier is exactly zero, the fit the same to the digit.
TEST(PlausibleCommands, IdentifyWithABoundFarAboveIsUnchanged) {
  const nlohmann::json free = Json(RunCli({"identify", "--model", Leg(), "--data", LoadedLegLog().string(), "--json"}));
  const nlohmann::json bounded = Json(
      RunCli({"identify", "--model", Leg(), "--data", LoadedLegLog().string(), "--total-mass", "100", "--json"}));
  ASSERT_EQ(free["bodies"].size(), bounded["bodies"].size());
  for (size_t k = 0; k < free["bodies"].size(); ++k) EXPECT_EQ(free["bodies"][k]["pi"], bounded["bodies"][k]["pi"]) << k;
  EXPECT_EQ(free["iterations"], bounded["iterations"]);
}

TEST(PlausibleCommands, IdentifyTakesARegionGivenByTheUser) {
  const testing::CliRun r = RunCli({"identify", "--model", Leg(), "--data", LoadedLegLog().string(), "--region",
                                    "shank=0,0,-0.2,0.08,0.08,0.3", "--json"});
  const nlohmann::json j = Json(r);
  ASSERT_EQ(j["bodies"].size(), 3u);
  EXPECT_EQ(j["bodies"][2]["plausibility"]["region"], "the user (--region)");
  EXPECT_EQ(j["bodies"][1]["plausibility"]["region"], "joints and prior");
  EXPECT_GE(j["bodies"][2]["plausibility"]["slack"].get<double>(), 0.0);
}

TEST(PlausibleCommands, BadRegionsAndMassesAreNamed) {
  const auto run = [](std::vector<std::string> extra) {
    std::vector<std::string> args{"identify", "--model", Leg(), "--data", LoadedLegLog().string()};
    args.insert(args.end(), extra.begin(), extra.end());
    return RunCli(args);
  };
  testing::CliRun r = run({"--region", "shin=0,0,0,0.1,0.1,0.1"});
  EXPECT_EQ(r.exit_code, 2) << Describe(r);
  EXPECT_TRUE(Contains(r.err, "Error: --region shin=0,0,0,0.1,0.1,0.1: there is no link 'shin' in the robot; the links "
                              "that move: abad_link, thigh, shank"))
      << r.err;
  r = run({"--region", "shank=0,0,0,0.1,0,0.1"});
  EXPECT_EQ(r.exit_code, 2) << Describe(r);
  EXPECT_TRUE(Contains(r.err, "Error: --region shank=0,0,0,0.1,0,0.1: semi-axis 2 is 0; every semi-axis must be positive"))
      << r.err;
  r = run({"--region", "shank=0,0,0,nan,0.1,0.1"});
  EXPECT_EQ(r.exit_code, 3) << Describe(r);
  EXPECT_TRUE(Contains(r.err, "--region shank") && Contains(r.err, "not finite")) << r.err;
  r = run({"--region", "shank=1,0,0,0.05,0.05,0.05"});
  EXPECT_EQ(r.exit_code, 2) << Describe(r);
  EXPECT_TRUE(Contains(r.err, "does not hold shank's prior")) << r.err;
  r = run({"--region", "base=0,0,0,0.1,0.1,0.1"});
  EXPECT_EQ(r.exit_code, 2) << Describe(r);
  EXPECT_TRUE(Contains(r.err, "fixed to the base")) << r.err;
  r = run({"--total-mass", "0"});
  EXPECT_EQ(r.exit_code, 2) << Describe(r);
  EXPECT_TRUE(Contains(r.err, "--total-mass: 0 is out of range")) << r.err;
  r = run({"--total-mass", "heavy"});
  EXPECT_EQ(r.exit_code, 3) << Describe(r);
  EXPECT_TRUE(Contains(r.err, "--total-mass")) << r.err;
  r = RunCli({"diagnose", "--body", "--data", LoadedLegLog().string(), "--total-mass", "3"});
  EXPECT_EQ(r.exit_code, 2) << Describe(r);
  EXPECT_TRUE(Contains(r.err, "--total-mass needs --model")) << r.err;
}

// identify writes a model file whose shank weighs about five times its URDF's; validate and check of
// that file call it implausible, against the prior the file records, as identify did.
TEST(PlausibleCommands, AnImplausibleModelFileIsCalledSoByValidateAndCheck) {
  const fs::path model = testing::UniqueTempPath("implausible.urdf");
  const testing::CliRun fit =
      RunCli({"identify", "--model", Leg(), "--data", LoadedLegLog().string(), "--write-urdf", model.string()});
  ASSERT_EQ(fit.exit_code, 0) << Describe(fit);
  EXPECT_TRUE(Contains(fit.out, "Warning: shank: ")) << fit.out;
  const testing::CliRun validate = RunCli({"validate", "--model", model.string(), "--data", LoadedLegLog().string()});
  EXPECT_EQ(validate.exit_code, 0) << Describe(validate);
  const testing::CliRun check = RunCli({"check", "--model", model.string()});
  EXPECT_EQ(check.exit_code, 0) << Describe(check);
  for (const testing::CliRun* r : {&validate, &check}) {
    EXPECT_TRUE(Contains(r->out, "Plausibility (links against the URDF priors the model file records")) << r->out;
    EXPECT_TRUE(Contains(r->out, "  shank: NOT plausible: region from joints and prior")) << r->out;
    EXPECT_TRUE(Contains(r->out, "(against recorded prior)")) << r->out;
    EXPECT_TRUE(Contains(r->out, "\nWarning: shank: ") && Contains(r->out, "times the URDF's 0.51 kg")) << r->out;
    EXPECT_TRUE(Contains(r->out, "  thigh: plausible")) << r->out;
  }
  const nlohmann::json j = Json(RunCli({"validate", "--model", model.string(), "--data", LoadedLegLog().string(), "--json"}));
  EXPECT_FALSE(j["plausible"].get<bool>());
  ASSERT_EQ(j["plausibility"].size(), 3u);
  EXPECT_EQ(j["plausibility"][2]["name"], "shank");
  EXPECT_EQ(j["plausibility"][2]["against"], "recorded prior");
  EXPECT_GT(j["plausibility"][2]["mass_ratio"].get<double>(), 3.0);
  const nlohmann::json c = Json(RunCli({"check", "--model", model.string(), "--json"}));
  EXPECT_FALSE(c["plausible"].get<bool>());
  EXPECT_FALSE(c["plausibility"][2]["plausible"].get<bool>());
  fs::remove(model);
}

// A hand-made arm whose upper arm weighs 196 kg (the other links 13.7 kg), its inertia as drawn for 4
// kg: denser than steel over its region, for check and validate; and heavier than the arm as weighed.
TEST(PlausibleCommands, AHundredAndNinetySixKilogramUpperArmIsImplausible) {
  std::string text = testing::ReadTextFile(testing::Example("arm7.urdf"));
  const std::size_t at = text.find("<mass value=\"4.0\"/>", text.find("<link name=\"link2\">"));
  ASSERT_NE(at, std::string::npos);
  text.replace(at, std::string("<mass value=\"4.0\"/>").size(), "<mass value=\"196\"/>");
  const fs::path urdf = testing::UniqueTempPath("arm196.urdf");
  testing::WriteTextFile(urdf, text);
  const testing::CliRun check = RunCli({"check", "--model", urdf.string(), "--total-mass", "33"});
  EXPECT_EQ(check.exit_code, 0) << Describe(check);
  EXPECT_TRUE(Contains(check.out, "  link2: NOT plausible: region from joints and prior")) << check.out;
  EXPECT_TRUE(Contains(check.out, "Warning: link2: denser than steel throughout its region")) << check.out;
  EXPECT_TRUE(Contains(check.out, "Total mass: 209.7 kg of links against the robot's 33 kg as weighed (--total-mass): "
                                  "NOT plausible: 209.7 kg is 6.35 times what the robot weighs"))
      << check.out;
  EXPECT_TRUE(Contains(check.out, "Warning: the links weigh 209.7 kg, more than the 33 kg the robot weighs")) << check.out;
  // validate of the same file on a log of the arm (the drawn arm's 2 s at 100 Hz).
  const RobotModel arm = LoadUrdf(testing::Example("arm7.urdf"));
  const RobotDynamics model = MakeRobotDynamics(arm, {});
  const testing::SimulatedLogs logs = testing::SimulateLogs(model, Eigen::VectorXd::Zero(model.num_parameters()), 0.05, 2.0, 43, 100);
  const fs::path log = testing::UniqueTempPath("arm.csv");
  WriteJointCsv(log.string(), logs.train);
  const testing::CliRun validate = RunCli({"validate", "--model", urdf.string(), "--data", log.string(), "--json"});
  const nlohmann::json j = Json(validate);
  EXPECT_FALSE(j["plausible"].get<bool>());
  EXPECT_FALSE(j["plausibility"][1]["plausible"].get<bool>());
  EXPECT_EQ(j["plausibility"][1]["against"], "itself");
  EXPECT_GT(j["plausibility"][1]["density"].get<double>(), 7850.0);
  EXPECT_TRUE(j["plausibility"][0]["plausible"].get<bool>());
  fs::remove(urdf);
  fs::remove(log);
}

// payload --region payload@LINK: the payload's region is the user's, and reported so.
TEST(PlausibleCommands, PayloadTakesARegionForThePayload) {
  const testing::CliRun r = RunCli({"payload", "--model", Leg(), "--data", LoadedLegLog().string(), "--link", "foot",
                                    "--region", "payload@foot=0,0,0,0.12,0.12,0.12", "--json"});
  const nlohmann::json j = Json(r);
  EXPECT_EQ(j["plausibility"]["region"], "the user (--region)") << r.out;
  const testing::CliRun bad = RunCli({"payload", "--model", Leg(), "--data", LoadedLegLog().string(), "--link", "foot",
                                      "--region", "payload@thigh=0,0,0,0.1,0.1,0.1"});
  EXPECT_EQ(bad.exit_code, 2) << Describe(bad);
  EXPECT_TRUE(Contains(bad.err, "the model has no payload@thigh")) << bad.err;
}

// diagnose with the weighed mass: every fit of the diagnosis keeps it, the final one reported.
TEST(PlausibleCommands, DiagnoseKeepsTheWeighedMass) {
  const testing::CliRun r = RunCli({"diagnose", "--model", Leg(), "--data", LoadedLegLog().string(), "--total-mass",
                                    "4.5", "--region", "thigh=0,0.02,-0.15,0.12,0.12,0.3", "--threads", "1", "--json"});
  const nlohmann::json j = Json(r);
  ASSERT_TRUE(j.contains("total_mass")) << r.out;
  EXPECT_TRUE(j["total_mass"]["within"].get<bool>());
  EXPECT_LE(j["total_mass"]["links"].get<double>(), 4.5);
}

// replay and inertiald take --region too: the online estimate's shank is judged against the given
// region; a bad one is refused before anything runs.
TEST(PlausibleCommands, ReplayAndInertialdTakeRegions) {
  const fs::path log = testing::UniqueTempPath("leg.lcm");
  testing::CliRun r = RunCli({"simulate", "--model", Leg(), "--write-log", log.string(), "--duration", "1", "--rate", "200"});
  ASSERT_EQ(r.exit_code, 0) << Describe(r);
  r = RunCli({"replay", "--model", Leg(), "--log", log.string(), "--region", "shank=0,0,-0.2,0.08,0.08,0.3"});
  EXPECT_EQ(r.exit_code, 0) << Describe(r);
  EXPECT_TRUE(Contains(r.out, "region from the user (--region)")) << r.out;
  r = RunCli({"replay", "--model", Leg(), "--log", log.string(), "--region", "shin=0,0,-0.2,0.08,0.08,0.3"});
  EXPECT_EQ(r.exit_code, 2) << Describe(r);
  EXPECT_TRUE(Contains(r.err, "Error: --region shin=0,0,-0.2,0.08,0.08,0.3: there is no link 'shin'")) << r.err;
  fs::remove(log);
  const char* daemon = std::getenv("INERTIALD");
  ASSERT_NE(daemon, nullptr);
  r = testing::RunProgram(daemon, {"--model", Leg(), "--region", "shin=0,0,0,0.1,0.1,0.1", "--lcm-url", "memq://"});
  EXPECT_EQ(r.exit_code, 2) << Describe(r);
  EXPECT_TRUE(Contains(r.err, "--region shin=0,0,0,0.1,0.1,0.1: there is no link 'shin'")) << r.err;
  r = testing::RunProgram(daemon, {"--model", Leg(), "--region", "shank=0,0,0,0.1,-1,0.1", "--lcm-url", "memq://"});
  EXPECT_EQ(r.exit_code, 2) << Describe(r);
  EXPECT_TRUE(Contains(r.err, "semi-axis 2 is -1")) << r.err;
}

}  // namespace
}  // namespace inertial
