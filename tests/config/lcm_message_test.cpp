// LCM messages: fingerprints against lcm-gen's, round trips through the generated encoders, a
// user's own message layout, and messages that must be refused (truncated, wrong fingerprint,
// lengths that disagree or are absurd, unknown joints, NaN, time going backwards), including
// 10^5 random corruptions.
#include <gtest/gtest.h>

#include "inertial/estimation/stream_preprocessor.hpp"

#include <cstdio>
#include <fstream>
#include <regex>

#include "cli_support.hpp"
#include "inertial/config/message_format.hpp"
#include "inertial/estimate_t.hpp"
#include "inertial/transport/body_message.hpp"
#include "inertial/transport/joint_message.hpp"
#include "inertial/joint_state_t.hpp"
#include "inertial/residual_t.hpp"
#include "inertial/body_wrench_t.hpp"
#include "test_support.hpp"

namespace inertial {
namespace {

namespace fs = std::filesystem;

LcmField F(const char* name, LcmType type, int length = -1, const char* length_field = "") {
  LcmField f;
  f.name = name;
  f.type = type;
  f.length = length;
  f.length_field = length_field;
  return f;
}

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

TEST(LcmLayout, FingerprintsAreLcmGens) {
  EXPECT_EQ(LcmFingerprint(JointStateLayout()), static_cast<std::uint64_t>(inertial::joint_state_t::getHash()));
  const LcmLayout residual{"residual_t",
                           {F("utime", LcmType::kInt64), F("status", LcmType::kString), F("num_channels", LcmType::kInt32),
                            F("channel_names", LcmType::kString, -1, "num_channels"),
                            F("measured", LcmType::kDouble, -1, "num_channels"),
                            F("predicted", LcmType::kDouble, -1, "num_channels"),
                            F("residual", LcmType::kDouble, -1, "num_channels")}};
  EXPECT_EQ(LcmFingerprint(residual), static_cast<std::uint64_t>(inertial::residual_t::getHash()));
  // Fixed-length arrays and booleans.
  EXPECT_EQ(LcmFingerprint(BodyWrenchLayout()), static_cast<std::uint64_t>(inertial::body_wrench_t::getHash()));
  // A foreign type from its JSON description, against lcm-gen run on its .lcm file.
  std::ifstream in(SourceDir() + "/tests/transport/data/leg_control_data_lcmt.json");
  const JointMessageFormat format = ParseJointMessageFormat(nlohmann::json::parse(in));
  EXPECT_EQ(LcmFingerprint(format.layout), LcmGenFingerprint(SourceDir() + "/tests/transport/data/leg_control_data_lcmt.lcm"));
}

JointSample Sample(double t, int n, testing::Rng& rng) {
  JointSample s;
  s.t = t;
  s.q = Eigen::VectorXd::Zero(n);
  s.qd = s.q;
  s.qdd = s.q;
  s.tau = s.q;
  for (int k = 0; k < n; ++k) {
    s.q[k] = rng.Uniform(-1, 1);
    s.qd[k] = rng.Uniform(-1, 1);
    s.qdd[k] = rng.Uniform(-1, 1);
    s.tau[k] = rng.Uniform(-5, 5);
  }
  return s;
}

const std::vector<std::string> kDofs{"abad", "hip", "knee"};

// Encoded by the generated code, decoded by ours, in another joint order: the same numbers.
TEST(JointMessage, RoundTripThroughTheGeneratedEncoder) {
  testing::Rng rng(1);
  const JointSample s = Sample(12.345678, 3, rng);
  // The message lists the joints as knee, abad, hip.
  JointSample permuted = s;
  const int order[3] = {2, 0, 1};
  for (int i = 0; i < 3; ++i) {
    permuted.q[i] = s.q[order[i]];
    permuted.qd[i] = s.qd[order[i]];
    permuted.qdd[i] = s.qdd[order[i]];
    permuted.tau[i] = s.tau[order[i]];
  }
  const std::vector<std::uint8_t> bytes = EncodeJointState({"knee", "abad", "hip"}, permuted);
  JointMessageDecoder decoder(JointMessageFormat{}, kDofs);
  JointSample out;
  std::string why;
  ASSERT_EQ(decoder.Decode(bytes.data(), bytes.size(), 0, &out, &why), Rejection::kNone) << why;
  EXPECT_NEAR(out.t, 12.345678, 1e-9);
  EXPECT_EQ(out.q, s.q);
  EXPECT_EQ(out.qd, s.qd);
  EXPECT_EQ(out.qdd, s.qdd);
  EXPECT_EQ(out.tau, s.tau);
  // The generated decoder reads our encoding back too.
  inertial::joint_state_t m;
  ASSERT_EQ(m.decode(bytes.data(), 0, static_cast<int>(bytes.size())), static_cast<int>(bytes.size()));
  EXPECT_EQ(m.joint_names[0], "knee");
}

// Big-endian writer for hand-made messages.
struct Writer {
  std::vector<std::uint8_t> bytes;
  void U64(std::uint64_t v) {
    for (int i = 7; i >= 0; --i) bytes.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
  }
  void F32(float f) {
    std::uint32_t u;
    std::memcpy(&u, &f, 4);
    for (int i = 3; i >= 0; --i) bytes.push_back(static_cast<std::uint8_t>(u >> (8 * i)));
  }
};

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

TEST(JointMessage, RefusesWhatItCannotTrust) {
  testing::Rng rng(2);
  const std::vector<std::uint8_t> good = EncodeJointState(kDofs, Sample(1.0, 3, rng));
  JointSample s;
  std::string why;
  auto decode = [&](const std::vector<std::uint8_t>& b, JointMessageDecoder& d) { return d.Decode(b.data(), b.size(), 0, &s, &why); };
  {
    JointMessageDecoder d(JointMessageFormat{}, kDofs);
    for (size_t cut = 0; cut < good.size(); ++cut) {
      const std::vector<std::uint8_t> truncated(good.begin(), good.begin() + static_cast<long>(cut));
      EXPECT_EQ(decode(truncated, d), Rejection::kDecode) << cut;
    }
    std::vector<std::uint8_t> longer = good;
    longer.push_back(0);
    EXPECT_EQ(decode(longer, d), Rejection::kDecode);
    EXPECT_NE(why.find("left over"), std::string::npos) << why;
    std::vector<std::uint8_t> hash = good;
    hash[3] ^= 0x10;
    EXPECT_EQ(decode(hash, d), Rejection::kDecode);
    EXPECT_NE(why.find("fingerprint"), std::string::npos) << why;
    for (std::int32_t n : {-1, 1 << 30, 5000}) {
      std::vector<std::uint8_t> absurd = good;
      for (int i = 0; i < 4; ++i) absurd[16 + i] = static_cast<std::uint8_t>(static_cast<std::uint32_t>(n) >> (8 * (3 - i)));
      EXPECT_EQ(decode(absurd, d), Rejection::kDecode) << n;
      EXPECT_NE(why.find("outside"), std::string::npos) << why;
    }
  }
  JointSample bad = Sample(2.0, 3, rng);
  {
    JointMessageDecoder d(JointMessageFormat{}, kDofs);
    EXPECT_EQ(decode(EncodeJointState({"abad", "hip", "ankle"}, bad), d), Rejection::kUnknownJoint);
    EXPECT_NE(why.find("ankle"), std::string::npos);
    JointSample two = bad;
    two.q.conservativeResize(2);
    two.qd.conservativeResize(2);
    two.qdd.conservativeResize(2);
    two.tau.conservativeResize(2);
    EXPECT_EQ(decode(EncodeJointState({"abad", "hip"}, two), d), Rejection::kWrongSize);
    EXPECT_NE(why.find("knee"), std::string::npos) << why;
    bad.tau[1] = std::nan("");
    EXPECT_EQ(decode(EncodeJointState(kDofs, bad), d), Rejection::kNonFinite);
    bad.tau[1] = 0.0;
    EXPECT_EQ(decode(EncodeJointState(kDofs, bad), d), Rejection::kNone);
    bad.t = 1.5;  // time order is the preprocessing stage's (stream_preprocessor_test.cpp)
    EXPECT_EQ(decode(EncodeJointState(kDofs, bad), d), Rejection::kNone);
  }
}

// 10^5 random corruptions (bytes flipped, inserted, removed, lengths rewritten) of valid messages:
// never a crash, and whatever is accepted is a finite, full-size sample.
TEST(JointMessage, SurvivesRandomCorruption) {
  testing::Rng rng(3);
  JointMessageDecoder d(JointMessageFormat{}, kDofs);
  JointSample s;
  int accepted = 0, refused = 0;
  for (int trial = 0; trial < 100000; ++trial) {
    std::vector<std::uint8_t> b = EncodeJointState(kDofs, Sample(1.0 + trial, 3, rng), trial % 2 == 0);
    const int edits = 1 + static_cast<int>(rng.Uniform(0, 4));
    for (int e = 0; e < edits; ++e) {
      const size_t at = static_cast<size_t>(rng.Uniform(0, static_cast<double>(b.size())));
      const double what = rng.Uniform(0, 1);
      if (what < 0.6 && at < b.size()) {
        b[at] = static_cast<std::uint8_t>(rng.Uniform(0, 256));
      } else if (what < 0.8) {
        b.insert(b.begin() + static_cast<long>(std::min(at, b.size())), static_cast<std::uint8_t>(rng.Uniform(0, 256)));
      } else if (!b.empty() && at < b.size()) {
        b.erase(b.begin() + static_cast<long>(at));
      }
    }
    if (d.Decode(b.data(), b.size(), 0, &s) == Rejection::kNone) {
      ++accepted;
      ASSERT_EQ(s.q.size(), 3);
      ASSERT_TRUE(s.q.allFinite() && s.qd.allFinite() && s.qdd.allFinite() && s.tau.allFinite());
    } else {
      ++refused;
    }
  }
  EXPECT_GT(refused, 50000);
  EXPECT_GT(accepted, 10);  // edits inside the numbers leave a valid message
}

// Body wrench messages: the generated encoder's bytes decode to the same sample; no twist, NaN and
// truncation are refused.
TEST(BodyMessage, RoundTripAndRefusals) {
  BodySample b;
  b.t = 3.25;
  for (int i = 0; i < 6; ++i) {
    b.twist[i] = 0.1 * i - 0.2;
    b.acceleration[i] = 1.0 - 0.3 * i;
    b.wrench[i] = 2.0 * i;
  }
  b.has_acceleration = true;
  b.gravity = Vector3(0, 0, -9.81);
  const std::vector<std::uint8_t> bytes = EncodeBodyWrench(b, "payload");
  BodySample out;
  std::string why;
  ASSERT_EQ(DecodeBodyWrench(bytes.data(), bytes.size(), &out, &why), Rejection::kNone) << why;
  EXPECT_EQ(out.t, 3.25);
  EXPECT_EQ(out.twist, b.twist);
  EXPECT_EQ(out.acceleration, b.acceleration);
  EXPECT_EQ(out.wrench, b.wrench);
  EXPECT_EQ(out.gravity, b.gravity);
  EXPECT_TRUE(out.has_acceleration);
  inertial::body_wrench_t m;
  ASSERT_EQ(m.decode(bytes.data(), 0, static_cast<int>(bytes.size())), static_cast<int>(bytes.size()));
  m.has_twist = false;
  std::vector<std::uint8_t> no_twist(static_cast<size_t>(m.getEncodedSize()));
  m.encode(no_twist.data(), 0, static_cast<int>(no_twist.size()));
  EXPECT_EQ(DecodeBodyWrench(no_twist.data(), no_twist.size(), &out, &why), Rejection::kWrongSize);
  b.wrench[4] = std::nan("");
  const std::vector<std::uint8_t> nan = EncodeBodyWrench(b, "payload");
  EXPECT_EQ(DecodeBodyWrench(nan.data(), nan.size(), &out, &why), Rejection::kNonFinite);
  EXPECT_EQ(DecodeBodyWrench(bytes.data(), bytes.size() - 1, &out, &why), Rejection::kDecode);
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
