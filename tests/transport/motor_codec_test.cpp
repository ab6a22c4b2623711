// Motor codecs against frames worked out by hand from the protocol descriptions (Mini Cheetah,
// linear fields), and 10^6 random frames through the codecs and the assembler.
#include "inertial/transport/motor_codec.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "inertial/transport/can_joint_assembler.hpp"
#include "test_support.hpp"
#include "transport/can_support.hpp"

namespace inertial {
namespace {

using testing::LegConfig;
using testing::MiniCheetah;
using testing::RandomFrame;

// Worked by hand from the protocol: x -> min + x (max - min) / (2^bits - 1).
TEST(MotorCodec, MiniCheetahFramesWorkedByHand) {
  const MotorConfig m = MiniCheetah(1);
  CanFrame f;
  f.id = 1;
  f.length = 6;
  const std::uint8_t middle[6] = {0x01, 0x80, 0x00, 0x80, 0x08, 0x00};  // p 0x8000, v 0x800, t 0x800
  std::copy(middle, middle + 6, f.data.begin());
  MotorReading r;
  ASSERT_EQ(DecodeMotorFrame(m, f, &r), Rejection::kNone);
  EXPECT_DOUBLE_EQ(r.q, -12.5 + 32768.0 * 25.0 / 65535.0);  // 1.907e-4 rad
  EXPECT_DOUBLE_EQ(r.qd, -65.0 + 2048.0 * 130.0 / 4095.0);  // 0.01587 rad/s
  EXPECT_DOUBLE_EQ(r.tau, -18.0 + 2048.0 * 36.0 / 4095.0);  // 0.004396 N m
  const std::uint8_t ends[6] = {0x01, 0x00, 0x00, 0xFF, 0xF0, 0x00};  // p 0 (min), v 0xFFF (max), t 0 (min)
  std::copy(ends, ends + 6, f.data.begin());
  ASSERT_EQ(DecodeMotorFrame(m, f, &r), Rejection::kNone);
  EXPECT_DOUBLE_EQ(r.q, -12.5);
  EXPECT_DOUBLE_EQ(r.qd, 65.0);
  EXPECT_DOUBLE_EQ(r.tau, -18.0);
  // Encoding: the same bytes back, saturation at the range ends.
  MotorReading big{0.0, 20.0, -100.0, 18.0};
  const CanFrame e = EncodeMotorFrame(m, big);
  EXPECT_EQ(e.length, 6);
  EXPECT_EQ(e.data[0], 0x01);
  EXPECT_EQ((e.data[1] << 8) | e.data[2], 0xFFFF);               // +12.5 rad
  EXPECT_EQ((e.data[3] << 4) | (e.data[4] >> 4), 0x000);          // -65 rad/s
  EXPECT_EQ(((e.data[4] & 0xF) << 8) | e.data[5], 0xFFF);         // +18 N m
  // Direction, gear and torque constant: a 6:1 motor-side reading, reversed, current in A.
  MotorConfig geared = m;
  geared.direction = -1;
  geared.gear = 6;
  geared.kt = 0.1;
  std::copy(middle, middle + 6, f.data.begin());
  ASSERT_EQ(DecodeMotorFrame(geared, f, &r), Rejection::kNone);
  EXPECT_DOUBLE_EQ(r.q, -(-12.5 + 32768.0 * 25.0 / 65535.0) / 6.0);
  EXPECT_DOUBLE_EQ(r.tau, -(-18.0 + 2048.0 * 36.0 / 4095.0) * 0.1 * 6.0);
  // Round trips within half a quantization step.
  testing::Rng rng(3);
  for (int i = 0; i < 1000; ++i) {
    const MotorReading in{0.0, rng.Uniform(-2, 2), rng.Uniform(-10, 10), rng.Uniform(-3, 3)};
    ASSERT_EQ(DecodeMotorFrame(geared, EncodeMotorFrame(geared, in), &r), Rejection::kNone);
    EXPECT_NEAR(r.q, in.q, 0.5 * 25.0 / 65535.0 / 6.0 + 1e-12);
    EXPECT_NEAR(r.qd, in.qd, 0.5 * 130.0 / 4095.0 / 6.0 + 1e-12);
    EXPECT_NEAR(r.tau, in.tau, 0.5 * 36.0 / 4095.0 * 0.6 + 1e-12);
  }
  // Malformed: short, wrong motor id in byte 0, remote.
  f.length = 5;
  std::string why;
  EXPECT_EQ(DecodeMotorFrame(m, f, &r, &why), Rejection::kMalformed);
  f.length = 6;
  f.data[0] = 7;
  EXPECT_EQ(DecodeMotorFrame(m, f, &r, &why), Rejection::kMalformed);
  EXPECT_NE(why.find("byte 0"), std::string::npos) << why;
  f.data[0] = 1;
  f.remote = true;
  EXPECT_EQ(DecodeMotorFrame(m, f, &r, &why), Rejection::kMalformed);
}

TEST(MotorCodec, LinearFieldsWorkedByHand) {
  MotorConfig m;
  m.can_id = 0x141;
  m.joint = "knee";
  m.protocol = MotorProtocol::kLinear;
  m.position = {0, 2, true, true, 0.001, 0.0};   // int16 little-endian, mrad
  m.velocity = {2, 2, false, false, 0.01, -5.0};  // uint16 big-endian, 0.01 rad/s, offset -5
  m.torque = {4, 4, true, false, 1e-4, 0.0};     // int32 big-endian
  CanFrame f;
  f.id = 0x141;
  f.length = 8;
  const std::uint8_t bytes[8] = {0x18, 0xFC, 0x01, 0xF4, 0xFF, 0xFF, 0x3C, 0xB0};
  std::copy(bytes, bytes + 8, f.data.begin());
  MotorReading r;
  ASSERT_EQ(DecodeMotorFrame(m, f, &r), Rejection::kNone);
  EXPECT_DOUBLE_EQ(r.q, -1.0);                 // 0xFC18 = -1000 mrad
  EXPECT_DOUBLE_EQ(r.qd, 500 * 0.01 - 5.0);    // 0x01F4 = 500
  EXPECT_NEAR(r.tau, -50000 * 1e-4, 1e-12);    // 0xFFFF3CB0 = -50000
  const CanFrame back = EncodeMotorFrame(m, r);
  EXPECT_TRUE(std::equal(bytes, bytes + 8, back.data.begin()));
}

// 10^6 random frames (any identifier, length, flags and bytes) into the codecs and the assembler:
// never a crash (the sanitizer build runs this too), and every reading that comes out is finite
// and within the configured ranges.
TEST(MotorCodec, SurvivesAMillionRandomFrames) {
  testing::Rng rng(9);
  CanConfig config = LegConfig();
  MotorConfig linear;
  linear.can_id = 0x141;
  linear.joint = "knee";
  linear.protocol = MotorProtocol::kLinear;
  linear.position = {0, 4, true, false, 1e-6, 0.0};
  linear.velocity = {60, 4, false, true, 1e-3, -1.0};
  linear.torque = {7, 1, true, true, 0.5, 0.0};
  config.motors[2] = linear;
  CanJointAssembler a(config, {"abad", "hip", "knee"});
  JointSample s;
  MotorReading r;
  int decoded = 0;
  for (int i = 0; i < 1000000; ++i) {
    CanFrame f = RandomFrame(rng);
    if (i % 3 == 0) f.id = static_cast<std::uint32_t>(rng.Uniform(0, 4)) == 3 ? 0x141 : static_cast<std::uint32_t>(rng.Uniform(1, 4));
    if (i % 5 == 0) f.data[0] = static_cast<std::uint8_t>(f.id & 0xFF);
    f.t = i * 1e-4;
    for (const MotorConfig& m : config.motors) {
      if (DecodeMotorFrame(m, f, &r) == Rejection::kNone) {
        ++decoded;
        ASSERT_TRUE(std::isfinite(r.q) && std::isfinite(r.qd) && std::isfinite(r.tau));
        if (m.protocol == MotorProtocol::kMiniCheetah) {
          ASSERT_LE(std::abs(r.q), 12.5);
          ASSERT_LE(std::abs(r.qd), 65.0);
          ASSERT_LE(std::abs(r.tau), 18.0);
        }
      }
    }
    if (a.Feed(f, &s)) {  // rare from random frames; checked when it happens
      ASSERT_TRUE(s.q.allFinite() && s.qd.allFinite() && s.qdd.allFinite() && s.tau.allFinite());
    }
  }
  EXPECT_GT(decoded, 1000);  // random frames that pass a motor's checks, decoded within its ranges
}

}  // namespace
}  // namespace inertial
