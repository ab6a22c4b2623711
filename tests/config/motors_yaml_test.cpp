// motors.yaml: a configuration with both protocols parsed, and every kind of mistake refused.
#include "inertial/config/motors_yaml.hpp"

#include <gtest/gtest.h>

#include <stdexcept>

namespace inertial {
namespace {

TEST(CanConfig, ParsesAndRefuses) {
  const CanConfig c = ParseCanConfig(R"(
window: 0.003
motors:
  - {id: 0x001, joint: abad, position: [-12.5, 12.5]}
  - id: 0x141
    joint: knee
    protocol: linear
    position: {byte: 0, width: 2, scale: 0.001}
    velocity: {byte: 2, width: 2, scale: 0.01}
    torque: {byte: 4, width: 2, scale: 0.01, endian: big}
)", "motors.yaml");
  ASSERT_EQ(c.motors.size(), 2u);
  EXPECT_EQ(c.motors[1].can_id, 0x141u);
  EXPECT_FALSE(c.motors[1].torque.little_endian);
  EXPECT_DOUBLE_EQ(c.window, 0.003);
  for (const char* bad : {"motors: []", "motors:\n  - {id: 0x800, joint: a}", "motors:\n  - {id: 1, joint: a, colour: red}",
                          "motors:\n  - {id: 1, joint: a}\n  - {id: 2, joint: a}", "motors:\n  - {id: 1, joint: a, protocol: canopen}",
                          "motors:\n  - {id: 1, joint: a, protocol: linear}", "motors:\n  - {id: x1, joint: a}",
                          "motors:\n  - {id: 1, joint: a, position: [3, 1]}", "motors: [", "speed: 3\nmotors: []",
                          "motors:\n  - {id: [1, 2], joint: a}", "motors:\n  - {id: 1, joint: [a, b]}",
                          "motors:\n  - {id: 1, joint: a, extended: maybe}", "motors:\n  - {id: 1, joint: a, motor_id: 1e20}",
                          "motors:\n  - {id: 1, joint: a, protocol: linear, position: {byte: 60}, velocity: {}, torque: {}}",
                          "motors:\n  - {id: 1, joint: a, protocol: linear, position: {width: 2.5}, velocity: {}, torque: {}}"}) {
    EXPECT_THROW(ParseCanConfig(bad, "bad.yaml"), std::invalid_argument) << bad;
  }
}

}  // namespace
}  // namespace inertial
