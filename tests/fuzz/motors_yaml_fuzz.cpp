// Fuzz harness: motors.yaml (motor_codec.hpp) as `inertiald --can-config` and `replay --candump`
// read it; an accepted configuration must encode and decode its own frames, and assemble them.
#include <cmath>

#include "fuzz_support.hpp"
#include "inertial/config/motors_yaml.hpp"
#include "inertial/transport/can_joint_assembler.hpp"
#include "inertial/transport/motor_codec.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace inertial;
  CanConfig config;
  try {
    config = ParseCanConfig(fuzz::Text(data, size), "motors.yaml");
  } catch (const std::invalid_argument&) {
    return 0;
  }
  if (config.motors.empty()) fuzz::Fail("a configuration without motors was accepted");
  std::vector<std::string> joints;
  for (const MotorConfig& m : config.motors) {
    joints.push_back(m.joint);
    MotorReading reading{0.0, 0.1, -0.2, 0.3}, back;
    const CanFrame frame = EncodeMotorFrame(m, reading);
    std::string why;
    if (DecodeMotorFrame(m, frame, &back, &why) != Rejection::kNone) fuzz::Fail("a motor's own frame is refused: " + why);
    if (!std::isfinite(back.q) || !std::isfinite(back.qd) || !std::isfinite(back.tau)) fuzz::Fail("a decoded value is not finite");
  }
  CanJointAssembler assembler(config, joints);
  JointSample sample;
  for (int tick = 0; tick < 3; ++tick) {
    for (const MotorConfig& m : config.motors) {
      CanFrame frame = EncodeMotorFrame(m, MotorReading{0.01 * tick, 0.1 * tick, 0.0, 0.0});
      frame.t = 0.01 * tick;
      assembler.Feed(frame, &sample);
    }
  }
  return 0;
}
