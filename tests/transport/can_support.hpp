/// @file can_support.hpp
/// Test helpers for CAN: random frames of every kind, a Mini Cheetah motor, a three-motor leg.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "inertial/transport/can_frame.hpp"
#include "inertial/transport/motor_codec.hpp"
#include "test_support.hpp"

namespace inertial::testing {

inline CanFrame RandomFrame(Rng& rng) {
  CanFrame f;
  const double seconds = std::floor(rng.Uniform(0, 2e9));  // drawn first, as GCC did (see testing::Rng)
  f.t = seconds + std::floor(rng.Uniform(0, 1e6)) * 1e-6;
  const double kind = rng.Uniform(0, 1);
  f.extended = kind < 0.4;
  f.id = static_cast<std::uint32_t>(rng.Uniform(0, f.extended ? 0x1FFFFFFF : 0x7FF));
  if (kind < 0.1) {
    f.remote = true;
    f.length = static_cast<std::uint8_t>(rng.Uniform(0, 9));
  } else if (kind < 0.2) {
    f.error = true;
    f.extended = false;
    f.length = 8;
  } else if (kind < 0.35) {
    f.fd = true;
    f.fd_flags = static_cast<std::uint8_t>(rng.Uniform(0, 4));
    const int sizes[] = {0, 5, 8, 12, 16, 20, 24, 32, 48, 64};
    f.length = static_cast<std::uint8_t>(sizes[static_cast<int>(rng.Uniform(0, 10))]);
  } else {
    f.length = static_cast<std::uint8_t>(rng.Uniform(0, 9));
  }
  if (!f.remote) {
    for (int i = 0; i < f.length; ++i) f.data[static_cast<size_t>(i)] = static_cast<std::uint8_t>(rng.Uniform(0, 256));
  }
  return f;
}

inline MotorConfig MiniCheetah(std::uint32_t id) {
  MotorConfig m;
  m.can_id = id;
  m.joint = "j" + std::to_string(id);
  return m;  // the protocol's usual ranges: p +-12.5 rad, v +-65 rad/s, t +-18 N m
}

inline CanConfig LegConfig() {
  CanConfig c;
  for (int k = 0; k < 3; ++k) {
    MotorConfig m = MiniCheetah(static_cast<std::uint32_t>(k + 1));
    m.joint = std::vector<std::string>{"abad", "hip", "knee"}[static_cast<size_t>(k)];
    c.motors.push_back(m);
  }
  return c;
}

}  // namespace inertial::testing
