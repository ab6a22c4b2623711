// motors.yaml: a configuration with both protocols parsed, and every kind of mistake refused.
#include "inertial/config/motors_yaml.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <stdexcept>

#include "cli_support.hpp"
#include "inertial/formats/input_file.hpp"
#include "test_support.hpp"

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

// Issue 35: one value of 1.5 million commas made yaml-cpp take 9.9 s and 1.4 GB before its error.
// Settings files over kMaxSettingsFileBytes are refused by their size, at once, from text or a file.
TEST(CanConfig, AFileOverTheSettingsLimitIsRefusedAtOnce) {
  const std::string text = "motors:\n  - id: 0x141\n    joint: knee\n    protocol: linear\n    position: {byte: 0, width: 2, scale: " +
                           std::string(1500000, ',') + "0.001}\n";
  std::string message;
  double seconds = testing::SecondsOf([&] {
    try {
      ParseCanConfig(text, "motors.yaml");
    } catch (const std::invalid_argument& e) {
      message = e.what();
    }
  });
  EXPECT_EQ(message, "motors.yaml: the motor configuration is " + std::to_string(text.size()) + " bytes, over its limit of 64 KiB: refused before parsing");
  EXPECT_LT(seconds, testing::kPromptSeconds);
  const std::string path = testing::WriteUniqueTempFile("motors.yaml", text);
  message.clear();
  seconds = testing::SecondsOf([&] {
    try {
      LoadCanConfig(path);
    } catch (const std::invalid_argument& e) {
      message = e.what();
    }
  });
  EXPECT_EQ(message, path + ": the motor configuration is " + std::to_string(text.size()) + " bytes, over its limit of 64 KiB: refused before parsing");
  EXPECT_LT(seconds, testing::kPromptSeconds);
  std::filesystem::remove(path);
  // Below the limit the commas are yaml-cpp's to refuse, as before: its message, not the size's.
  try {
    ParseCanConfig("motors:\n  - {id: 1, joint: a, position: {scale: " + std::string(1000, ',') + "1}}\n", "m.yaml");
    ADD_FAILURE() << "1000 commas were accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()).find("refused before parsing"), std::string::npos) << e.what();
    EXPECT_EQ(std::string(e.what()).rfind("m.yaml: ", 0), 0u) << e.what();
  }
}

}  // namespace
}  // namespace inertial
