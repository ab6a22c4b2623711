/// @file can_frame.hpp
/// One CAN frame, classic or FD, as SocketCAN and candump see it, and the candump log format
/// (`candump -l`): lines `(seconds.micros) iface ID#DATA`, where ID is 3 hex digits (11-bit) or 8
/// (29-bit, extended), DATA is hex bytes optionally separated by '.', `ID#R` or `ID#R<len>` is a
/// remote frame, `ID##<flags><data>` a CAN FD frame (one hex digit of flags: 1 = bit-rate switch,
/// 2 = error-state indicator), an ID with the error flag (0x20000000) an error frame, and a
/// trailing direction marker (` R` or ` T`) may follow.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <string_view>

namespace inertial {

struct CanFrame {
  double t = 0.0;           ///< reception time [s]
  std::uint32_t id = 0;     ///< 11 or 29 bits (without the flags below)
  bool extended = false;    ///< 29-bit identifier
  bool remote = false;      ///< remote transmission request (no data)
  bool error = false;       ///< an error frame (id holds the error class bits)
  bool fd = false;          ///< CAN FD (up to 64 data bytes)
  std::uint8_t fd_flags = 0;  ///< CAN FD: 1 bit-rate switch, 2 error-state indicator
  std::uint8_t length = 0;  ///< data length (for a remote frame: the requested length)
  std::array<std::uint8_t, 64> data{};
};

/// Valid CAN FD payload sizes: 0-8, 12, 16, 20, 24, 32, 48, 64.
bool IsValidFdLength(int length);

/// What a candump log line holds.
enum class CandumpLine { kFrame, kNotAFrame };

/// Parses one line of a candump log. A line that is not a frame (blank, a comment, another tool's
/// output) gives kNotAFrame with *why; a line that looks like a frame but is malformed (bad hex,
/// an 11-bit ID above 0x7FF, more than 8 (classic) or 64 (FD) bytes, an invalid FD length, odd
/// hex digits) throws std::invalid_argument naming what is wrong.
CandumpLine ParseCandumpLine(std::string_view line, CanFrame* frame, std::string* interface, std::string* why = nullptr);

/// The candump -l line of a frame (no trailing newline).
std::string FormatCandumpLine(const CanFrame& frame, const std::string& interface);

}  // namespace inertial
