// Usage errors of `inertial` and `inertiald` as a new user meets them (tools/command_line.hpp): the
// program, the subcommand and the unknown word named, with the nearest known one; --version.
#include <gtest/gtest.h>

#include <cstdlib>

#include "cli_support.hpp"

namespace inertial {
namespace {

using testing::Contains;
using testing::Describe;
using testing::RunCli;

TEST(CommandLine, AnUnknownSubcommandIsNamedWithTheNearestAndTheList) {
  testing::CliRun r = RunCli({"bogus"});
  EXPECT_EQ(r.exit_code, 2) << Describe(r);
  EXPECT_TRUE(Contains(r.err, "Error: inertial: unknown subcommand 'bogus'; the subcommands are study, convert, identify"))
      << Describe(r);
  r = RunCli({"idnetify", "--model", "x.urdf"});
  EXPECT_EQ(r.exit_code, 2) << Describe(r);
  EXPECT_TRUE(Contains(r.err, "unknown subcommand 'idnetify' (did you mean identify?)")) << Describe(r);
  r = RunCli({});
  EXPECT_EQ(r.exit_code, 2) << Describe(r);
  EXPECT_TRUE(Contains(r.err, "Error: inertial: a subcommand is required: study, convert")) << Describe(r);
}

TEST(CommandLine, VersionIsPrinted) {
  const testing::CliRun r = RunCli({"--version"});
  EXPECT_EQ(r.exit_code, 0) << Describe(r);
  EXPECT_EQ(r.out, "inertial " INERTIAL_TEST_VERSION "\n") << Describe(r);
  const char* daemon = std::getenv("INERTIALD");
  ASSERT_NE(daemon, nullptr);
  const testing::CliRun d = testing::RunProgram(daemon, {"--version"});
  EXPECT_EQ(d.exit_code, 0) << Describe(d);
  EXPECT_EQ(d.out, "inertiald " INERTIAL_TEST_VERSION "\n") << Describe(d);
}

TEST(CommandLine, AnUnknownOptionIsNamedWithTheNearestOrTheSubcommandThatHasIt) {
  testing::CliRun r = RunCli({"identify", "--model", "a.urdf", "--data", "a.csv", "--holdout", "0.3"});
  EXPECT_EQ(r.exit_code, 2) << Describe(r);
  EXPECT_TRUE(Contains(r.err, "Error: inertial identify: unknown option --holdout (it is an option of inertial diagnose)"))
      << Describe(r);
  r = RunCli({"diagnose", "--model", "a.urdf", "--data", "a.csv", "--hold-link"});
  EXPECT_EQ(r.exit_code, 2) << Describe(r);
  EXPECT_TRUE(Contains(r.err, "Error: inertial diagnose: unknown option --hold-link (did you mean --hold-links?)"))
      << Describe(r);
  r = RunCli({"convert", "--from", "pi", "--to", "theta", "--bogus"});
  EXPECT_EQ(r.exit_code, 2) << Describe(r);
  EXPECT_TRUE(Contains(r.err, "Error: inertial convert: unknown option --bogus")) << Describe(r);
  // Negative numbers are values, not options.
  r = RunCli({"convert", "--from", "theta", "--to", "pi", "--", "0", "-0.5", "0", "0", "0", "0", "0", "0", "0", "0"});
  EXPECT_EQ(r.exit_code, 0) << Describe(r);
  const char* daemon = std::getenv("INERTIALD");
  ASSERT_NE(daemon, nullptr);
  r = testing::RunProgram(daemon, {"--model", "a.urdf", "--chanel", "X"});
  EXPECT_EQ(r.exit_code, 2) << Describe(r);
  EXPECT_TRUE(Contains(r.err, "Error: inertiald: unknown option --chanel (did you mean --channel?)")) << Describe(r);
}

}  // namespace
}  // namespace inertial
