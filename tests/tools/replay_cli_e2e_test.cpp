// `inertial replay` end to end: a log that gives the estimator nothing is an error that says why
// (exit 6), never a "final estimate" equal to the prior.
#include <gtest/gtest.h>

#include <fstream>

#include "cli_support.hpp"
#include "simulated_robot.hpp"

namespace inertial {
namespace {

using testing::Contains;
using testing::Describe;
using testing::RunCli;
namespace fs = std::filesystem;

class ReplayCli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = testing::UniqueTempPath("replay");
    fs::create_directories(dir_);
    leg_ = testing::Example("leg3.urdf");
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
  std::string leg_;
};

TEST_F(ReplayCli, ALogWithoutTheChannelIsAnErrorListingTheChannelsItHas) {
  const std::string log = (dir_ / "leg.lcm").string();  // 1 s at 200 Hz: 201 samples, both ends
  testing::CliRun r = RunCli({"simulate", "--model", leg_, "--write-log", log, "--log-channel", "LEG_STATE",
                              "--duration", "1", "--rate", "200"});
  ASSERT_EQ(r.exit_code, 0) << Describe(r);
  r = RunCli({"replay", "--model", leg_, "--log", log});
  EXPECT_EQ(r.exit_code, 6) << Describe(r);
  EXPECT_TRUE(Contains(r.err, "no message on channel INERTIAL_JOINT_STATE; LEG_STATE (201 messages); choose one with --channel"))
      << Describe(r);
  EXPECT_FALSE(Contains(r.out, "final estimate")) << Describe(r);
  // The channel it has works.
  r = RunCli({"replay", "--model", leg_, "--log", log, "--channel", "LEG_STATE"});
  EXPECT_EQ(r.exit_code, 0) << Describe(r);
  EXPECT_TRUE(Contains(r.out, "final estimate")) << Describe(r);
}

TEST_F(ReplayCli, MessagesOfJointsTheModelDoesNotHaveAreAnError) {
  const std::string log = (dir_ / "arm.lcm").string();
  testing::CliRun r = RunCli({"simulate", "--model", testing::Example("arm7.urdf"), "--write-log", log, "--duration", "1",
                              "--rate", "100"});
  ASSERT_EQ(r.exit_code, 0) << Describe(r);
  r = RunCli({"replay", "--model", leg_, "--log", log});
  EXPECT_EQ(r.exit_code, 6) << Describe(r);
  EXPECT_TRUE(Contains(r.err, "every one of the 101 messages on INERTIAL_JOINT_STATE was refused:")) << Describe(r);
  EXPECT_TRUE(Contains(r.err, "the messages name joints the --model does not have")) << Describe(r);
}

TEST_F(ReplayCli, AnEmptyOrBinaryCandumpFileIsAnError) {
  std::ofstream(dir_ / "motors.yaml") << R"(motors:
  - {id: 0x001, joint: abad, protocol: mini_cheetah, position: [-12.5, 12.5], velocity: [-65, 65], torque: [-18, 18]}
  - {id: 0x002, joint: hip, protocol: mini_cheetah, position: [-12.5, 12.5], velocity: [-65, 65], torque: [-18, 18]}
  - {id: 0x003, joint: knee, protocol: mini_cheetah, position: [-12.5, 12.5], velocity: [-65, 65], torque: [-18, 18]}
)";
  std::ofstream(dir_ / "empty.log").flush();
  {
    std::ofstream binary(dir_ / "binary.log", std::ios::binary);
    for (int i = 0; i < 4096; ++i) binary.put(static_cast<char>((i * 7919) & 0xff));
  }
  for (const char* name : {"empty.log", "binary.log"}) {
    const testing::CliRun r = RunCli({"replay", "--model", leg_, "--candump", (dir_ / name).string(), "--can-config",
                                      (dir_ / "motors.yaml").string()});
    EXPECT_EQ(r.exit_code, 6) << name << ": " << Describe(r);
    EXPECT_TRUE(Contains(r.err, "gave the estimator no sample")) << Describe(r);
    EXPECT_TRUE(Contains(r.err, "none is a candump frame")) << Describe(r);
    EXPECT_FALSE(Contains(r.out, "final estimate")) << Describe(r);
  }
}

}  // namespace
}  // namespace inertial
