// CAN end to end: `inertial simulate --write-candump` and `inertial replay --candump` with a
// motors.yaml (a mini-cheetah-protocol and a generic linear driver), the candump log cross-read by
// can-utils; and inertiald on a real SocketCAN virtual interface (vcan) fed by can-utils' canplayer,
// in the test's own network namespace, where the kernel has CAN (skipped, with the reason, where it
// has none: this machine's kernel has no AF_CAN).
#include <gtest/gtest.h>

#include <fstream>

#include "cli_support.hpp"
#include "inertial/transport/can_bus.hpp"
#include "simulated_robot.hpp"

namespace inertial {
namespace {

namespace fs = std::filesystem;
using testing::Contains;
using testing::Describe;
using testing::RunCli;

const char* kMotors = R"(window: 0.002
accel_cutoff_hz: 30
motors:
  - {id: 0x001, joint: abad, protocol: mini_cheetah, position: [-12.5, 12.5], velocity: [-65, 65], torque: [-18, 18]}
  - {id: 0x002, joint: hip, protocol: mini_cheetah, position: [-12.5, 12.5], velocity: [-65, 65], torque: [-18, 18], direction: -1}
  - id: 0x141
    joint: knee
    protocol: linear
    position: {byte: 0, width: 2, signed: true, endian: little, scale: 0.0005}
    velocity: {byte: 2, width: 2, signed: true, endian: little, scale: 0.002}
    torque: {byte: 4, width: 2, signed: true, endian: big, scale: 0.001}
)";

TEST(CanCli, SimulateAndReplayACandumpLog) {
  const fs::path dir = testing::UniqueTempPath("can");
  fs::create_directories(dir);
  std::ofstream(dir / "motors.yaml") << kMotors;
  const std::string leg = testing::Example("leg3.urdf");
  testing::CliRun r = RunCli({"simulate", "--model", leg, "--write-candump", (dir / "leg.log").string(), "--can-config",
                              (dir / "motors.yaml").string(), "--duration", "10", "--perturb", "0.2", "--noise-tau", "0.1"});
  ASSERT_EQ(r.exit_code, 0) << Describe(r);
  // Lines that are not frames and malformed lines, as a real log may hold.
  {
    std::ofstream(dir / "leg.log", std::ios::app) << "# end of capture\n(99.000000) can0 123#GG\n";
  }
  r = RunCli({"replay", "--model", leg, "--candump", (dir / "leg.log").string(), "--can-config",
              (dir / "motors.yaml").string(), "--noise-tau", "0.1"});
  ASSERT_EQ(r.exit_code, 0) << Describe(r);
  // 5001 samples of 3 motors and the malformed line; the first tick primes the preprocessing
  // stage's acceleration filter. Nothing else is refused (no reason but these two is listed).
  EXPECT_TRUE(Contains(r.out, "15004 frame lines; accepted 5000, rejected 2 (priming 1, bad_line 1)")) << r.out;
  EXPECT_TRUE(Contains(r.out, "CAN: 5001 complete ticks;")) << r.out;
  EXPECT_TRUE(Contains(r.out, "1 lines that are not frames")) << r.out;
  // Bad input.
  r = RunCli({"replay", "--model", leg, "--candump", (dir / "leg.log").string()});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Contains(r.err, "--can-config")) << Describe(r);
  std::ofstream(dir / "bad.yaml") << "motors:\n  - {id: 0x001, joint: abad}\n";
  r = RunCli({"replay", "--model", leg, "--candump", (dir / "leg.log").string(), "--can-config", (dir / "bad.yaml").string()});
  EXPECT_EQ(r.exit_code, 5);  // a settings file that is not valid: a file error, as a bad URDF
  EXPECT_TRUE(Contains(r.err, "'hip' has no motor")) << Describe(r);
  fs::remove_all(dir);
}

TEST(CanCli, InertialdOnAVirtualCanInterface) {
  std::string why;
  if (!SocketCanAvailable(&why)) GTEST_SKIP() << "no SocketCAN here: " << why;
  for (const char* tool : {"/usr/bin/unshare", "/usr/bin/canplayer", "/usr/bin/ip", "/usr/bin/lcm-logger"}) {
    if (!fs::exists(tool) && !fs::exists(std::string("/sbin/") + fs::path(tool).filename().string())) {
      GTEST_SKIP() << tool << " is not installed";
    }
  }
  const testing::CliRun probe = testing::RunProgram("/usr/bin/unshare",
                                                    {"-rn", "/bin/sh", "-c", "ip link add dev vcan0 type vcan"});
  if (probe.exit_code != 0) GTEST_SKIP() << "cannot create a vcan interface in a namespace: " << Describe(probe);
  const char* daemon = std::getenv("INERTIALD");
  ASSERT_NE(daemon, nullptr);
  const fs::path dir = testing::UniqueTempPath("vcan");
  fs::create_directories(dir);
  std::ofstream(dir / "motors.yaml") << kMotors;
  const std::string leg = testing::Example("leg3.urdf");
  const testing::CliRun sim = RunCli({"simulate", "--model", leg, "--write-candump", (dir / "leg.log").string(),
                                      "--can-config", (dir / "motors.yaml").string(), "--duration", "3"});
  ASSERT_EQ(sim.exit_code, 0) << Describe(sim);
  std::ofstream(dir / "run.sh") << "set -u\ncd '" << dir.string() << "'\n"
                                << "ip link set lo up\nip link add dev vcan0 type vcan\nip link set up vcan0\n"
                                << "'" << daemon << "' --model '" << leg << "' --can vcan0 --can-config motors.yaml "
                                << "--lcm-url memq:// --checkpoint state.json 2> daemon.err & D=$!\nsleep 0.7\n"
                                << "canplayer -I leg.log vcan0=can0\nsleep 0.5\nkill -TERM $D; wait $D; echo \"exit $?\"\n";
  const testing::CliRun run = testing::RunProgram("/usr/bin/unshare", {"-rn", "/bin/bash", (dir / "run.sh").string()});
  ASSERT_EQ(run.exit_code, 0) << Describe(run);
  EXPECT_TRUE(Contains(run.out, "exit 0")) << run.out;
  const std::string err = testing::ReadFile(dir / "daemon.err");
  EXPECT_TRUE(Contains(err, "received 4503")) << err;  // 1501 ticks x 3 motors
  EXPECT_TRUE(fs::exists(dir / "state.json"));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace inertial
