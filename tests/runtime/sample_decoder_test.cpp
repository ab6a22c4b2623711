#include "inertial/runtime/sample_decoder.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "inertial/transport/body_message.hpp"

namespace inertial {
namespace {

const std::vector<std::string> kDofs{"abad", "hip", "knee"};

JointSample Joints(double t) {
  JointSample s;
  s.t = t;
  s.q = Eigen::Vector3d(0.1, 0.2, 0.3);
  s.qd = Eigen::Vector3d(1, 2, 3);
  s.qdd = Eigen::Vector3d(4, 5, 6);
  s.tau = Eigen::Vector3d(7, 8, 9);
  return s;
}

TEST(SampleDecoder, JointMessagesAreDecodedAndCounted) {
  JointMessageFormat format;
  format.accel_cutoff_hz = 33.0;
  SampleDecoder d = SampleDecoder::JointMessages(format, kDofs);
  EXPECT_FALSE(d.body_mode());
  EXPECT_FALSE(d.can_mode());
  EXPECT_EQ(d.accel_cutoff_hz(), 33.0);
  Sample s = Sample::ForJoints(3);
  const std::vector<std::uint8_t> with = EncodeJointState(kDofs, Joints(1.0), true);
  const std::vector<std::uint8_t> without = EncodeJointState(kDofs, Joints(1.1), false);
  ASSERT_TRUE(d.DecodeMessage(with.data(), with.size(), 0, &s));
  EXPECT_TRUE(s.joint.has_qdd);
  EXPECT_EQ(s.joint.qdd, Eigen::VectorXd(Eigen::Vector3d(4, 5, 6)));
  ASSERT_TRUE(d.DecodeMessage(without.data(), without.size(), 0, &s));
  EXPECT_FALSE(s.joint.has_qdd);  // left to the preprocessing stage
  std::string why;
  EXPECT_FALSE(d.DecodeMessage(with.data(), with.size() - 1, 0, &s, &why));
  EXPECT_EQ(d.last_rejection(), Rejection::kDecode);
  EXPECT_FALSE(why.empty());
  const SampleCounters c = d.counters();
  EXPECT_EQ(c.received, 3u);
  EXPECT_EQ(c.accepted, 2u);
  EXPECT_EQ(c[Rejection::kDecode], 1u);
}

TEST(SampleDecoder, BodyWrenches) {
  SampleDecoder d = SampleDecoder::BodyWrenches();
  EXPECT_TRUE(d.body_mode());
  BodySample b;
  b.t = 2.0;
  b.twist << 1, 2, 3, 4, 5, 6;
  b.wrench << 6, 5, 4, 3, 2, 1;
  const std::vector<std::uint8_t> m = EncodeBodyWrench(b, "payload");
  Sample s;
  ASSERT_TRUE(d.DecodeMessage(m.data(), m.size(), 0, &s));
  EXPECT_EQ(s.body.wrench, b.wrench);
  EXPECT_DOUBLE_EQ(s.time(true), 2.0);
  EXPECT_FALSE(d.DecodeMessage(m.data(), m.size() / 2, 0, &s));
  EXPECT_EQ(d.counters()[Rejection::kDecode], 1u);
}

TEST(SampleDecoder, CanFramesAndBadLines) {
  CanConfig config;
  config.window = 0.002;
  config.accel_cutoff_hz = 15.0;
  for (int k = 0; k < 3; ++k) {
    MotorConfig m;
    m.can_id = static_cast<std::uint32_t>(0x10 + k);
    m.joint = kDofs[static_cast<std::size_t>(k)];
    config.motors.push_back(m);
  }
  SampleDecoder d = SampleDecoder::CanFrames(config, kDofs);
  EXPECT_TRUE(d.can_mode());
  EXPECT_EQ(d.accel_cutoff_hz(), 15.0);
  ASSERT_EQ(d.can_ids().size(), 3u);
  EXPECT_EQ(d.can_ids()[2].id, 0x12u);
  Sample s = Sample::ForJoints(3);
  bool tick = false;
  for (int k = 0; k < 3; ++k) {
    tick = d.DecodeFrame(EncodeMotorFrame(config.motors[static_cast<std::size_t>(k)], MotorReading{1e-4 * k, 0.1, 0.2, 0.3}), &s);
    if (k < 2) EXPECT_EQ(d.last_rejection(), Rejection::kNone);  // waiting for the others
  }
  ASSERT_TRUE(tick);
  EXPECT_FALSE(s.joint.has_qdd);
  CanFrame error;
  error.error = true;
  EXPECT_FALSE(d.DecodeFrame(error, &s));
  EXPECT_EQ(d.last_rejection(), Rejection::kErrorFrame);
  d.CountBadLine();
  const SampleCounters c = d.counters();
  EXPECT_EQ(c.received, 5u);  // four frames and the line that was not one
  EXPECT_EQ(c.accepted, 1u);
  EXPECT_EQ(c[Rejection::kErrorFrame], 1u);
  EXPECT_EQ(c[Rejection::kBadLine], 1u);
}

}  // namespace
}  // namespace inertial
