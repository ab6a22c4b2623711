// The message formats of the daemon's configuration: LCM layouts from JSON (a foreign type's
// fingerprint against lcm-gen's, bad layouts refused) and a foreign joint message (the Cheetah's
// leg_control_data_lcmt) decoded through its layout from a config file.
#include "inertial/config/message_format.hpp"

#include <gtest/gtest.h>

#include "inertial/signal/stream_preprocessor.hpp"

#include <cstdio>
#include <fstream>
#include <regex>

#include "cli_support.hpp"
#include "inertial/estimate_t.hpp"
#include "transport/big_endian_writer.hpp"
#include "inertial/transport/joint_message.hpp"
#include "test_support.hpp"

namespace inertial {
namespace {

namespace fs = std::filesystem;
using testing::Writer;

std::string SourceDir() {
  const char* dir = std::getenv("INERTIAL_SOURCE_DIR");
  return dir != nullptr ? dir : ".";
}

// The fingerprint lcm-gen writes into a generated header (the base hash, rotated as getHash does).
std::uint64_t LcmGenFingerprint(const fs::path& lcm_file) {
  const fs::path out = testing::UniqueTempPath("lcmgen");
  fs::create_directories(out);
  const testing::CliRun r = testing::RunProgram("/usr/bin/lcm-gen", {"--cpp", "--cpp-hpath", out.string(), lcm_file.string()});
  EXPECT_EQ(r.exit_code, 0) << testing::Describe(r);
  std::string header;
  for (const auto& e : fs::recursive_directory_iterator(out)) {
    if (e.path().extension() == ".hpp") header = testing::ReadFile(e.path());
  }
  fs::remove_all(out);
  std::smatch m;
  EXPECT_TRUE(std::regex_search(header, m, std::regex("uint64_t hash = 0x([0-9a-f]+)LL;"))) << header.substr(0, 500);
  const std::uint64_t base = std::stoull(m[1].str(), nullptr, 16);
  return (base << 1) + ((base >> 63) & 1);
}

// The project's own types are checked in tests/transport/lcm_layout_test.cpp.
TEST(LcmLayout, ForeignFingerprintIsLcmGens) {
  // A foreign type from its JSON description, against lcm-gen run on its .lcm file.
  std::ifstream in(SourceDir() + "/tests/transport/data/leg_control_data_lcmt.json");
  const JointMessageFormat format = ParseJointMessageFormat(nlohmann::json::parse(in));
  EXPECT_EQ(LcmFingerprint(format.layout), LcmGenFingerprint(SourceDir() + "/tests/transport/data/leg_control_data_lcmt.lcm"));
}

const std::vector<std::string> kDofs{"abad", "hip", "knee"};

// The Cheetah-style foreign layout: fixed float arrays of 12 joints, no names (a list in the
// config), no time (the receive time), no accelerations (the causal difference of qd).
TEST(JointMessage, AForeignLayoutFromAConfigFile) {
  std::ifstream in(SourceDir() + "/tests/transport/data/leg_control_data_lcmt.json");
  const JointMessageFormat format = ParseJointMessageFormat(nlohmann::json::parse(in));
  JointMessageDecoder decoder(format, kDofs);
  auto message = [&](double phase) {
    Writer w;
    w.U64(LcmFingerprint(format.layout));
    for (int block = 0; block < 5; ++block) {
      for (int k = 0; k < 12; ++k) w.F32(static_cast<float>(block == 1 ? 0.5 * phase * (k + 1) : block + 0.01 * k));
    }
    return w.bytes;
  };
  JointSample s;
  std::vector<std::uint8_t> m0 = message(0.0), m1 = message(1.0);
  // The decoder only decodes (has_qdd false); the preprocessing stage derives qdd, the first
  // sample priming its filter.
  StreamPreprocessor preprocess(static_cast<int>(kDofs.size()), format.accel_cutoff_hz);
  ASSERT_EQ(decoder.Decode(m0.data(), m0.size(), 1000000, &s), Rejection::kNone);
  EXPECT_FALSE(s.has_qdd);
  EXPECT_EQ(preprocess.Process(&s), Rejection::kPriming);
  ASSERT_EQ(decoder.Decode(m1.data(), m1.size(), 1010000, &s), Rejection::kNone);
  ASSERT_EQ(preprocess.Process(&s), Rejection::kNone);
  EXPECT_TRUE(s.has_qdd);
  EXPECT_DOUBLE_EQ(s.t, 1.01);
  EXPECT_FLOAT_EQ(static_cast<float>(s.q[1]), 0.01f);          // q block, joint 1
  EXPECT_FLOAT_EQ(static_cast<float>(s.tau[2]), 4.02f);        // tau_est block, joint 2
  // qd went from 0 to 0.5 (k + 1) in 10 ms: the low-passed difference, alpha = dt / (dt + 1/(2 pi 30)).
  const double alpha = 0.01 / (0.01 + 1.0 / (2 * M_PI * 30));
  EXPECT_NEAR(s.qdd[0], alpha * 0.5 / 0.01, 1e-4);
  EXPECT_NEAR(s.qdd[2], alpha * 1.5 / 0.01, 1e-4);
}

TEST(LcmLayout, RejectsBadLayouts) {
  EXPECT_THROW(ParseLcmLayout(nlohmann::json::parse(R"({"fields": [{"name": "a", "type": "quaternion"}]})")),
               std::invalid_argument);
  EXPECT_THROW(ParseLcmLayout(nlohmann::json::parse(R"({"fields": [{"name": "a", "type": "double", "length": "n"}]})")),
               std::invalid_argument);
  EXPECT_THROW(ParseLcmLayout(nlohmann::json::parse(R"({"fields": [{"name": "a", "type": "double"}, {"name": "a", "type": "float"}]})")),
               std::invalid_argument);
  EXPECT_THROW(ParseJointMessageFormat(nlohmann::json::parse(R"({"q": 3})")), std::invalid_argument);
  JointMessageFormat f;
  f.tau = "torque";
  EXPECT_THROW(JointMessageDecoder(f, kDofs), std::invalid_argument);
  JointMessageFormat array_time;
  array_time.utime_field = "qdd";  // a variable-length array cannot be the time
  EXPECT_THROW(JointMessageDecoder(array_time, kDofs), std::invalid_argument);
  EXPECT_THROW(ParseJointMessageFormat(nlohmann::json::parse(R"({"joint_names": [1, 2, 3]})")), std::invalid_argument);
  EXPECT_THROW(ParseLcmLayout(nlohmann::json::parse(R"({"fields": [{"name": "a", "type": "double", "length": 5000}]})")),
               std::invalid_argument);
}

}  // namespace
}  // namespace inertial
