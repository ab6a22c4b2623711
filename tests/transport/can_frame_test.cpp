// The candump -l format: every case of the format, round trips and a cross-check with can-utils'
// log2long and log2asc, 10^6 random and mutated lines.
#include "inertial/transport/can_frame.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <regex>
#include <sstream>

#include "cli_support.hpp"
#include "test_support.hpp"
#include "transport/can_support.hpp"

namespace inertial {
namespace {

namespace fs = std::filesystem;
using testing::RandomFrame;

CanFrame Parse(const std::string& line, std::string* iface = nullptr) {
  CanFrame f;
  std::string name;
  EXPECT_EQ(ParseCandumpLine(line, &f, &name), CandumpLine::kFrame) << line;
  if (iface) *iface = name;
  return f;
}

TEST(Candump, EveryCaseOfTheFormat) {
  std::string iface;
  CanFrame f = Parse("(1436509052.249713) vcan0 123#DEADBEEF", &iface);
  EXPECT_EQ(iface, "vcan0");
  EXPECT_NEAR(f.t, 1436509052.249713, 1e-6);
  EXPECT_EQ(f.id, 0x123u);
  EXPECT_FALSE(f.extended);
  ASSERT_EQ(f.length, 4);
  EXPECT_EQ(f.data[0], 0xDE);
  EXPECT_EQ(f.data[3], 0xEF);
  f = Parse("(0.000001) can1 1F334455#11.22.33");  // extended, '.' separators
  EXPECT_TRUE(f.extended);
  EXPECT_EQ(f.id, 0x1F334455u);
  EXPECT_EQ(f.length, 3);
  EXPECT_EQ(f.data[2], 0x33);
  f = Parse("(1.5) can0 321#R");
  EXPECT_TRUE(f.remote);
  EXPECT_EQ(f.length, 0);
  f = Parse("(1.5) can0 321#R5");
  EXPECT_TRUE(f.remote);
  EXPECT_EQ(f.length, 5);
  f = Parse("(2.000000) can0 123##10123456789ABCDEF");  // FD, flags 1 (bit-rate switch), 8 bytes
  EXPECT_TRUE(f.fd);
  EXPECT_EQ(f.fd_flags, 1);
  EXPECT_EQ(f.length, 8);
  EXPECT_EQ(f.data[7], 0xEF);
  f = Parse("(2.0) can0 123##2" + std::string(24, 'A'));  // FD, 12 bytes, ESI
  EXPECT_EQ(f.length, 12);
  EXPECT_EQ(f.fd_flags, 2);
  f = Parse("(3.0) can0 20000004#0004000000000000");  // an error frame (controller problem)
  EXPECT_TRUE(f.error);
  EXPECT_EQ(f.id, 0x4u);
  EXPECT_EQ(f.length, 8);
  f = Parse("(4.0) can0 123#00 R");  // direction markers
  EXPECT_EQ(f.length, 1);
  f = Parse("(4.0) can0 123#0102 T");
  EXPECT_EQ(f.length, 2);
  f = Parse("(5.0) can0 7FF#");  // no data
  EXPECT_EQ(f.length, 0);
  std::string why;
  const std::string huge_time = "(" + std::string(400, '9') + ".0) can0 123#00";
  for (const std::string& not_frame : {std::string(""), std::string("   "), std::string("# a comment"),
                                       std::string("Timestamp: 1.0 ID: 123"), std::string("(1.0)"),
                                       std::string("(abc) can0 123#00"), std::string("(1.0) can0 123#00 X"), huge_time}) {
    EXPECT_EQ(ParseCandumpLine(not_frame, &f, &iface, &why), CandumpLine::kNotAFrame) << not_frame;
  }
  for (const char* bad : {"(1.0) can0 800#00", "(1.0) can0 12#00", "(1.0) can0 123#0", "(1.0) can0 123#GG",
                          "(1.0) can0 123#010203040506070809", "(1.0) can0 123##1010203040506070809",
                          "(1.0) can0 123#R9", "(1.0) can0 3FFFFFFFF#00", "(1.0) can0 123#0.1"}) {
    EXPECT_THROW(ParseCandumpLine(bad, &f, &iface, &why), std::invalid_argument) << bad;
  }
}

bool Same(const CanFrame& a, const CanFrame& b) {
  return std::abs(a.t - b.t) < 1e-6 && a.id == b.id && a.extended == b.extended && a.remote == b.remote &&
         a.error == b.error && a.fd == b.fd && (!a.fd || a.fd_flags == b.fd_flags) && a.length == b.length &&
         (a.remote || std::equal(a.data.begin(), a.data.begin() + a.length, b.data.begin()));
}

TEST(Candump, RoundTripsAndAgreesWithLog2longAndLog2asc) {
  testing::Rng rng(1);
  const fs::path log = testing::UniqueTempPath("round.log");
  std::vector<CanFrame> frames;
  {
    std::ofstream out(log);
    for (int i = 0; i < 2000; ++i) {
      CanFrame f = RandomFrame(rng);
      if (f.fd || f.error) continue;  // log2long of can-utils 2020.11 prints classic frames
      f.t = 1000.0 + 0.001 * i;       // a log's times increase (log2asc restarts at a backward jump)
      frames.push_back(f);
      out << FormatCandumpLine(f, "can0") << "\n";
      CanFrame back;
      std::string iface;
      ASSERT_EQ(ParseCandumpLine(FormatCandumpLine(f, "can0"), &back, &iface), CandumpLine::kFrame);
      ASSERT_TRUE(Same(f, back)) << FormatCandumpLine(f, "can0");
    }
  }
  for (int i = 0; i < 2000; ++i) {  // FD and error frames round-trip too
    CanFrame f = RandomFrame(rng), back;
    std::string iface;
    ASSERT_EQ(ParseCandumpLine(FormatCandumpLine(f, "vcan1"), &back, &iface), CandumpLine::kFrame);
    ASSERT_TRUE(Same(f, back)) << FormatCandumpLine(f, "vcan1");
  }
  // can-utils' log2long reads the same file: its identifier, length and bytes are ours.
  if (!fs::exists("/usr/bin/log2long")) GTEST_SKIP() << "can-utils' log2long is not installed";
  const testing::CliRun r = testing::RunProgram("/usr/bin/log2long", {}, testing::ReadFile(log));
  ASSERT_EQ(r.exit_code, 0) << testing::Describe(r);
  std::istringstream lines(r.out);
  std::string line;
  size_t k = 0;
  const std::regex pattern(R"(^\(([0-9.]+)\)\s+can0\s+([0-9A-F]+)\s+\[(\d)\]\s*((?:[0-9A-F]{2} )*|remote request))");
  while (std::getline(lines, line) && k < frames.size()) {
    std::smatch m;
    ASSERT_TRUE(std::regex_search(line, m, pattern)) << line;
    const CanFrame& f = frames[k++];
    EXPECT_EQ(std::stoul(m[2].str(), nullptr, 16), f.id) << line;
    EXPECT_EQ(std::stoi(m[3].str()), f.length) << line;
    if (!f.remote) {
      std::string bytes;
      char buf[4];
      for (int i = 0; i < f.length; ++i) {
        std::snprintf(buf, sizeof buf, "%02X ", f.data[static_cast<size_t>(i)]);
        bytes += buf;
      }
      EXPECT_EQ(m[4].str(), bytes) << line;
    }
  }
  EXPECT_EQ(k, frames.size());
  // And can-utils' log2asc (Vector ASC): identifier with 'x' when extended, 'd' data or 'r' remote,
  // length and bytes.
  if (!fs::exists("/usr/bin/log2asc")) GTEST_SKIP() << "can-utils' log2asc is not installed";
  const testing::CliRun asc = testing::RunProgram("/usr/bin/log2asc", {"-I", log.string(), "can0"});
  ASSERT_EQ(asc.exit_code, 0) << testing::Describe(asc);
  std::istringstream asc_lines(asc.out);
  const std::regex asc_pattern(R"(^\s+[0-9.]+ 1\s+([0-9A-F]+)(x?)\s+Rx\s+([dr]) (\d+)((?: [0-9A-F]{2})*)\s*$)");
  k = 0;
  while (std::getline(asc_lines, line)) {
    std::smatch m;
    if (!std::regex_search(line, m, asc_pattern)) continue;  // headers: date, base, ...
    ASSERT_LT(k, frames.size()) << line;
    const CanFrame& f = frames[k++];
    EXPECT_EQ(std::stoul(m[1].str(), nullptr, 16), f.id) << line;
    EXPECT_EQ(m[2].str() == "x", f.extended) << line;
    EXPECT_EQ(m[3].str() == "r", f.remote) << line;
    EXPECT_EQ(std::stoi(m[4].str()), f.length) << line;
    if (!f.remote) {
      std::string bytes;
      char buf[4];
      for (int i = 0; i < f.length; ++i) {
        std::snprintf(buf, sizeof buf, " %02X", f.data[static_cast<size_t>(i)]);
        bytes += buf;
      }
      EXPECT_EQ(m[5].str(), bytes) << line;
    }
  }
  EXPECT_EQ(k, frames.size());
  fs::remove(log);
}

// 10^6 random and mutated lines: never a crash; anything accepted formats and parses back the same.
TEST(Candump, SurvivesAMillionRandomLines) {
  testing::Rng rng(2);
  const std::string alphabet = "0123456789ABCDEFabcdef#.()R T rx\t-:";
  int frames = 0, not_frames = 0, errors = 0;
  for (int i = 0; i < 1000000; ++i) {
    std::string line;
    if (i % 2 == 0) {
      line = FormatCandumpLine(RandomFrame(rng), "can0");
      const int edits = 1 + static_cast<int>(rng.Uniform(0, 3));
      for (int e = 0; e < edits && !line.empty(); ++e) {
        const size_t at = static_cast<size_t>(rng.Uniform(0, static_cast<double>(line.size())));
        line[at] = alphabet[static_cast<size_t>(rng.Uniform(0, static_cast<double>(alphabet.size())))];
      }
    } else {
      const int n = static_cast<int>(rng.Uniform(0, 60));
      line = "(1.0) can0 ";
      for (int c = 0; c < n; ++c) line += alphabet[static_cast<size_t>(rng.Uniform(0, static_cast<double>(alphabet.size())))];
    }
    CanFrame f;
    std::string iface;
    try {
      if (ParseCandumpLine(line, &f, &iface) == CandumpLine::kFrame) {
        ++frames;
        CanFrame back;
        ASSERT_EQ(ParseCandumpLine(FormatCandumpLine(f, iface), &back, &iface), CandumpLine::kFrame) << line;
        ASSERT_TRUE(Same(f, back)) << line;
      } else {
        ++not_frames;
      }
    } catch (const std::invalid_argument&) {
      ++errors;
    }
  }
  EXPECT_GT(frames, 1000);
  EXPECT_GT(not_frames, 1000);
  EXPECT_GT(errors, 1000);
}

}  // namespace
}  // namespace inertial
