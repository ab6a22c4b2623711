/// @file big_endian_writer.hpp
/// Test helper: a big-endian writer for hand-made LCM messages.
#pragma once

#include <cstdint>
#include <cstring>
#include <vector>

namespace inertial::testing {

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

}  // namespace inertial::testing
