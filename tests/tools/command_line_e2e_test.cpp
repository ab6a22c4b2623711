// Usage errors of `inertial` and `inertiald` as a new user meets them (tools/command_line.hpp): the
// program, the subcommand and the unknown word named, with the nearest known one; --version.
#include <gtest/gtest.h>

#include <cstdlib>
#include <regex>
#include <set>
#include <sstream>

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

// Every numeric option shows its type, unit and default one way (tools/numeric_options.hpp):
// "--name TYPE [unit]=default", and nothing that takes a number still shows TEXT. The options that
// may show TEXT are those whose value is a path, a name, or a list of words.
TEST(CommandLine, EveryNumericOptionShowsTypeUnitAndDefaultOneWay) {
  const std::set<std::string> words = {
      "--model", "--data", "--validate", "--effects", "--predictions", "--write-urdf", "--report", "--out",
      "--write-log", "--log-channel", "--write-candump", "--can-config", "--truth", "--truth-urdf", "--repair",
      "--log", "--candump", "--channel", "--config", "--estimator", "--from", "--to", "--state", "--lcm-url",
      "--estimate-channel", "--residual-channel", "--checkpoint", "--can", "--log-level", "--format", "--urdf",
      "--baseline", "--link"};
  const std::regex line(R"(^  (--[a-z-]+) ([A-Z0-9][A-Z0-9 ]*?)( \[[^\]]+\])?(=.*?)?(\s{2,}.*)?$)");
  const std::regex numeric_type(R"(^(INT|FLOAT|FLOATS|\d+ FLOATS)$)");
  int numeric = 0;
  auto check = [&](const std::string& program, const std::vector<std::string>& args) {
    const testing::CliRun r = testing::RunProgram(program, args);
    ASSERT_EQ(r.exit_code, 0) << Describe(r);
    std::istringstream in(r.out);
    for (std::string text; std::getline(in, text);) {
      std::smatch m;
      if (!std::regex_match(text, m, line)) continue;
      const std::string name = m[1], type = m[2];
      if (type.rfind("TEXT", 0) == 0) {
        EXPECT_TRUE(words.count(name) == 1) << args[0] << ": " << text;
      } else if (type != "REQUIRED") {
        EXPECT_TRUE(std::regex_match(type, numeric_type)) << args[0] << ": " << text;
        ++numeric;
      }
    }
  };
  const char* cli = std::getenv("INERTIAL_CLI");
  const char* daemon = std::getenv("INERTIALD");
  ASSERT_NE(cli, nullptr);
  ASSERT_NE(daemon, nullptr);
  for (const char* sub : {"study", "convert", "identify", "check", "simulate", "replay", "diagnose", "export", "validate",
                          "payload"}) {
    check(cli, {sub, "--help"});
  }
  check(daemon, {"--help"});
  EXPECT_GE(numeric, 50);  // the table covers the numeric options of all ten commands
  // The shape itself, on two examples.
  const testing::CliRun r = RunCli({"identify", "--help"});
  EXPECT_TRUE(Contains(r.out, "--sg-window FLOAT [s]=0.1")) << r.out;
  EXPECT_TRUE(Contains(r.out, "--gravity 3 FLOATS [m/s^2]=0 0 -9.81")) << r.out;
}

}  // namespace
}  // namespace inertial
