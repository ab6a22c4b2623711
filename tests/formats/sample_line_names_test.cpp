#include "inertial/formats/sample_line_names.hpp"

#include <gtest/gtest.h>

namespace inertial {
namespace {

TEST(SampleLineNames, MessagesNamingASampleGetItsFileLine) {
  // Sample 0 on line 2 (after the header), sample 2 on line 5 (a bad row skipped before it).
  const std::vector<int> lines = {2, 3, 5};
  std::vector<std::string> messages = {"sample 2: residual 9 robust sd", "sample 0 (t = 0 s)", "no row named",
                                       "sample 3 beyond the log", "the sample 1 of tau"};
  NameSamplesByLine("run.csv", lines, &messages);
  EXPECT_EQ(messages, (std::vector<std::string>{"run.csv:5: sample 2: residual 9 robust sd",
                                                "run.csv:2: sample 0 (t = 0 s)", "no row named",
                                                "sample 3 beyond the log", "run.csv:3: the sample 1 of tau"}));
}

TEST(SampleLineNames, RunsLaidEndToEndNameTheirOwnFile) {
  // a.csv's samples 0, 1 on lines 2, 3; b.csv's (samples 2, 3) on lines 2, 4.
  std::vector<std::string> messages = {"sample 1: x", "sample 3: y", "sample 2 (t = 9 s)"};
  NameSamplesByLine({"a.csv", "b.csv"}, {0, 2, 4}, {2, 3, 2, 4}, &messages);
  EXPECT_EQ(messages, (std::vector<std::string>{"a.csv:3: sample 1: x", "b.csv:4: sample 3: y", "b.csv:2: sample 2 (t = 9 s)"}));
}

TEST(SampleLineNames, NoLinesLeavesEveryMessage) {
  std::vector<std::string> messages = {"sample 0"};
  NameSamplesByLine("run.csv", {}, &messages);
  EXPECT_EQ(messages[0], "sample 0");
}

}  // namespace
}  // namespace inertial
