// Streams without accelerations (issue 46, part 1), as a new user meets them: the robot sends q, qd
// and tau, no qdd. `replay` of such a stream (an LCM log of inertial.joint_state_t without qdd, a
// candump log of mini-cheetah motors with 12-bit velocities, a CSV log without qdd columns) fits
// the filtered momentum rows (momentum_rows.hpp) where qdd was not measured, with default options.
// Judged as a user judges it: `validate` of the written model on another log of the same robot;
// the reference is `identify` on the same run's CSV with the exact qdd. Bound: 1.1 times the
// reference's held-out error.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_support.hpp"
#include "simulated_robot.hpp"

namespace inertial {
namespace {

using testing::Describe;
using testing::RunCli;
namespace fs = std::filesystem;

const char* kLegMotors = R"(window: 0.002
motors:
  - {id: 0x001, joint: abad, protocol: mini_cheetah, position: [-12.5, 12.5], velocity: [-65, 65], torque: [-18, 18]}
  - {id: 0x002, joint: hip, protocol: mini_cheetah, position: [-12.5, 12.5], velocity: [-65, 65], torque: [-18, 18]}
  - {id: 0x003, joint: knee, protocol: mini_cheetah, position: [-12.5, 12.5], velocity: [-65, 65], torque: [-18, 18]}
)";

struct Case {
  std::string robot, effects, values;
};

TEST(OnlineWithoutQdd, SimulatedStreamsWithinTenPercentOfTheBatchFitOnExactQdd) {
  const fs::path dir = testing::UniqueTempPath("online-no-qdd");
  fs::create_directories(dir);
  std::ofstream(dir / "motors.yaml") << kLegMotors;
  const auto path = [&](const std::string& name) { return (dir / name).string(); };
  for (const Case& c : {Case{"leg3.urdf", "coulomb@hip,viscous@knee", "0.2,0.3"}, Case{"arm7.urdf", "viscous", "0.1"}}) {
    const std::string model = testing::Example(c.robot);
    const std::vector<std::string> sim = {"simulate", "--model", model, "--effects", c.effects, "--effect-values", c.values,
                                          "--perturb", "0.2", "--noise-tau", "0.02", "--noise-qd", "0.005"};
    const auto simulate = [&](std::vector<std::string> extra) {
      std::vector<std::string> args = sim;
      args.insert(args.end(), extra.begin(), extra.end());
      const testing::CliRun r = RunCli(args);
      ASSERT_EQ(r.exit_code, 0) << Describe(r);
    };
    // One run written three ways (the same seed: the same motion and noise), and a held-out run.
    simulate({"--out", path("train.csv")});
    simulate({"--positions-only", "--write-log", path("train.lcm")});  // q, qd, tau: no qdd
    simulate({"--out", path("test.csv"), "--duration", "8", "--seed", "2"});
    testing::DropAccelerations(path("train.csv"), path("train-no-qdd.csv"));
    const double batch = testing::HeldOutError(testing::FitToUrdf({"identify", "--model", model, "--data", path("train.csv")}, c.effects, path("batch.urdf")),
                                 path("test.csv"));
    const double lcm = testing::HeldOutError(testing::FitToUrdf({"replay", "--model", model, "--log", path("train.lcm")}, c.effects, path("lcm.urdf")),
                               path("test.csv"));
    const double csv = testing::HeldOutError(
        testing::FitToUrdf({"replay", "--model", model, "--log", path("train-no-qdd.csv")}, c.effects, path("csv.urdf")), path("test.csv"));
    std::cerr << c.robot << ": batch on exact qdd " << batch << ", LCM without qdd " << lcm << ", CSV without qdd " << csv << "\n";
    EXPECT_LE(lcm, 1.1 * batch) << c.robot << ": LCM without qdd " << lcm << ", batch on exact qdd " << batch;
    EXPECT_LE(csv, 1.1 * batch) << c.robot << ": CSV without qdd " << csv << ", batch on exact qdd " << batch;
    if (c.robot == "leg3.urdf") {
      simulate({"--write-candump", path("train.can"), "--can-config", path("motors.yaml")});
      const double can = testing::HeldOutError(testing::FitToUrdf({"replay", "--model", model, "--candump", path("train.can"), "--can-config",
                                      path("motors.yaml")},
                                     c.effects, path("can.urdf")),
                                 path("test.csv"));
      std::cerr << "candump " << can << "\n";
      EXPECT_LE(can, 1.1 * batch) << "candump (12-bit velocities) " << can << ", batch on exact qdd " << batch;
    }
  }
  fs::remove_all(dir);
}

TEST(OnlineWithoutQdd, KukaLwr4WithoutItsAccelerationColumns) {
  const char* source = std::getenv("INERTIAL_SOURCE_DIR");
  const std::string data = std::string(source != nullptr ? source : ".") + "/../shared/data/kuka_lwr4";
  if (!fs::exists(data + "/measurements_1.csv")) {
    GTEST_SKIP() << "real data absent: " << data << " does not exist (see ../shared/data/README)";
  }
  const fs::path dir = testing::UniqueTempPath("online-no-qdd-kuka");
  fs::create_directories(dir);
  const std::string model = data + "/kuka_lwr4.urdf", effects = "offset,viscous,coulomb";
  const std::string train = (dir / "run1-no-qdd.csv").string();
  testing::DropAccelerations(data + "/measurements_1.csv", train);
  const double batch = testing::HeldOutError(testing::FitToUrdf({"identify", "--model", model, "--data", data + "/measurements_1.csv"}, effects,
                                   (dir / "batch.urdf").string()),
                               data + "/measurements_2.csv");
  const double online =
      testing::HeldOutError(testing::FitToUrdf({"replay", "--model", model, "--log", train}, effects, (dir / "online.urdf").string()),
              data + "/measurements_2.csv");
  std::cerr << "KUKA run 1 -> run 2: batch on exact qdd " << batch << ", online without qdd " << online << "\n";
  EXPECT_LE(online, 1.1 * batch) << "online without qdd " << online << ", batch on exact qdd " << batch;
  fs::remove_all(dir);
}

}  // namespace
}  // namespace inertial
