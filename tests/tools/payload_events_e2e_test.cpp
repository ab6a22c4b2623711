// `inertial replay --json` payload events end to end (issue 46, part 2): the bundled arm simulated by
// `inertial simulate` in three logs that continue one another (--start-time), the middle one
// carrying a payload on tool0 (--effects payload@tool0:mass=2, perturbed as the links: the truth
// is read back from --truth-urdf), joined into one pick and place; replayed with default options,
// with and without the qdd columns. The events must name link7 (tool0 is fixed to it), their
// onsets the 0.1 s block of the change, be emitted within 2 s of it, and carry the true mass
// within 10 % and within 4 of their stds. Clean logs (the arm and the leg, friction in the model
// and the truth) and the real KUKA LWR4+ logs must give no event.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "cli_support.hpp"
#include "simulated_robot.hpp"

namespace inertial {
namespace {

using testing::Describe;
using testing::RunCli;
namespace fs = std::filesystem;

// The first <mass value="..."/> after `<payload link=` in a model file written by --truth-urdf.
double PayloadMass(const std::string& urdf_text) {
  const size_t payload = urdf_text.find("<payload link=");
  EXPECT_NE(payload, std::string::npos) << "no payload in the truth model";
  const size_t mass = urdf_text.find("<mass value=\"", payload);
  EXPECT_NE(mass, std::string::npos);
  return std::stod(urdf_text.substr(mass + 13));
}

// `text`'s lines without its header and first data line (t = start, the previous log's last).
std::string WithoutHeaderAndFirstRow(const std::string& text) {
  size_t cut = text.find('\n');
  cut = text.find('\n', cut + 1);
  return text.substr(cut + 1);
}

nlohmann::json ReplayJson(const std::vector<std::string>& args) {
  std::vector<std::string> all = {"replay"};
  all.insert(all.end(), args.begin(), args.end());
  all.push_back("--json");
  const testing::CliRun r = RunCli(all);
  EXPECT_EQ(r.exit_code, 0) << Describe(r);
  return nlohmann::json::parse(r.out);
}

class PayloadEvents : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = testing::UniqueTempPath("payload-events");
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

// 2 kg (perturbed to 2.222 kg) at tool0 from 20 s to 40 s of a 60 s excitation at 500 Hz, 0.1 N m
// of torque noise, links 10 % off the URDF.
TEST_F(PayloadEvents, PickAndPlaceOnTheArmWithAndWithoutQdd) {
  const std::string arm = testing::Example("arm7.urdf");
  std::string joined;
  for (int part = 0; part < 3; ++part) {
    const fs::path out = dir_ / ("part" + std::to_string(part) + ".csv");
    std::vector<std::string> sim = {"simulate", "--model", arm, "--out", out.string(), "--perturb", "0.1", "--noise-tau",
                                    "0.1", "--duration", "20", "--seed", "1", "--start-time", std::to_string(20 * part)};
    if (part == 1) {
      sim.insert(sim.end(), {"--effects", "payload@tool0:mass=2", "--truth-urdf", (dir_ / "truth.urdf").string()});
    }
    const testing::CliRun r = RunCli(sim);
    ASSERT_EQ(r.exit_code, 0) << Describe(r);
    const std::string text = testing::ReadFile(out);
    joined += part == 0 ? text : WithoutHeaderAndFirstRow(text);
  }
  const double mass = PayloadMass(testing::ReadFile(dir_ / "truth.urdf"));
  const fs::path log = dir_ / "pick.csv", noqdd = dir_ / "pick_noqdd.csv";
  std::ofstream(log) << joined;
  testing::DropAccelerations(log.string(), noqdd.string());
  for (const fs::path& input : {log, noqdd}) {
    SCOPED_TRACE(input.filename().string());
    const nlohmann::json j = ReplayJson({"--model", arm, "--log", input.string()});
    const nlohmann::json& events = j.at("payload_events");
    ASSERT_EQ(events.size(), 2u) << j.dump(2);
    for (int k = 0; k < 2; ++k) {
      const nlohmann::json& e = events[static_cast<size_t>(k)];
      std::cerr << e.at("text").get<std::string>() << "\n";
      const double change = k == 0 ? 20.0 : 40.0, sign = k == 0 ? 1.0 : -1.0;
      EXPECT_EQ(e.at("link"), "link7");
      EXPECT_NEAR(e.at("onset_time").get<double>(), change - 0.05, 0.051);
      EXPECT_LE(e.at("settle_time").get<double>(), change + 2.0);
      EXPECT_TRUE(e.at("settled").get<bool>());
      const double m = e.at("added_mass").get<double>(), s = e.at("added_mass_std").get<double>();
      EXPECT_NEAR(m, sign * mass, 0.10 * mass);
      EXPECT_NEAR(m, sign * mass, 4 * s);
      EXPECT_TRUE(k == 0 ? e.contains("ur_script") : true);  // a pick-up in the controllers' forms
    }
  }
}

// Ten clean logs (the arm and the leg, five trajectories each; links 20 % off the URDF, viscous and
// Coulomb friction 0.2 in the truth and in the model; 0.1 N m of noise; 40 s at 500 Hz): no event.
TEST_F(PayloadEvents, NoEventOnTenCleanLogs) {
  for (const std::string robot : {"arm7", "leg3"}) {
    for (int seed = 1; seed <= 5; ++seed) {
      const std::string model = testing::Example(robot + ".urdf");
      const fs::path log = dir_ / (robot + std::to_string(seed) + ".csv");
      const testing::CliRun r =
          RunCli({"simulate", "--model", model, "--out", log.string(), "--perturb", "0.2", "--noise-tau", "0.1", "--duration",
                  "40", "--seed", std::to_string(seed), "--effects", "viscous,coulomb", "--effect-values", "0.2"});
      ASSERT_EQ(r.exit_code, 0) << Describe(r);
      const nlohmann::json j = ReplayJson({"--model", model, "--log", log.string(), "--effects", "viscous,coulomb"});
      EXPECT_TRUE(j.at("payload_events").empty()) << robot << " seed " << seed << ": " << j.at("payload_events").dump(2);
    }
  }
}

// The real KUKA LWR4+ logs (25 s each, filtered at 2 Hz, the model 10 % off): no event.
TEST_F(PayloadEvents, NoEventOnTheKukaLogs) {
  const std::string data = testing::SharedKukaData();
  if (data.empty()) GTEST_SKIP() << "real data absent: ../shared/data/kuka_lwr4 does not exist (see ../shared/data/README)";
  for (const std::string file : {"measurements_1.csv", "measurements_2.csv"}) {
    const nlohmann::json j = ReplayJson({"--model", data + "/kuka_lwr4.urdf", "--log", data + "/" + file});
    EXPECT_TRUE(j.at("payload_events").empty()) << file << ": " << j.at("payload_events").dump(2);
  }
}

}  // namespace
}  // namespace inertial
