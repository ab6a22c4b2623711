// Joint-state messages: the generated encoder's bytes decoded by ours in another joint order (and
// ours by the generated decoder), refusals of what cannot be trusted, 10^5 random corruptions.
#include "inertial/transport/joint_message.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "inertial/joint_state_t.hpp"
#include "test_support.hpp"

namespace inertial {
namespace {

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

}  // namespace
}  // namespace inertial
