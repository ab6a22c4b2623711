// Body wrench messages: the generated encoder's bytes decode to the same sample; no twist, NaN and
// truncation are refused.
#include "inertial/transport/body_message.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "inertial/body_wrench_t.hpp"

namespace inertial {
namespace {

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

}  // namespace
}  // namespace inertial
