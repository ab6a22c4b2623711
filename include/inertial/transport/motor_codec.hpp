/// @file motor_codec.hpp
/// Motor-driver CAN frames into joint readings, configured per motor (motors.yaml, read by
/// config/motors_yaml.hpp).
///
/// Protocols:
/// - mini_cheetah: the reply frame of the open mini-cheetah-style motor driver (many commercial
///   actuators use it): 6 data bytes, byte 0 the motor's id, then a 16-bit position (bytes 1-2,
///   big-endian), a 12-bit velocity (byte 3 and the high nibble of byte 4) and a 12-bit torque or
///   current (the low nibble of byte 4 and byte 5), each an unsigned integer x mapped linearly onto
///   its range: value = min + x (max - min) / (2^bits - 1).
/// - linear: any other driver, each of position, velocity and torque read from its own bytes
///   (offset, width 1/2/4, signed or not, big- or little-endian) as value = raw * scale + offset.
/// Joint values: q = direction (p / gear) + zero, qd = direction v / gear,
/// tau = direction * torque_field * kt * gear (kt: N m per unit of the field, 1 when it is torque).
///
/// motors.yaml:
///   window: 0.002            # s: a tick is complete when every joint reported within it
///   accel_cutoff_hz: 20      # qdd from qd by the preprocessing stage (stream_preprocessor.hpp)
///   motors:
///     - {id: 0x001, joint: abad, protocol: mini_cheetah, position: [-12.5, 12.5],
///        velocity: [-65, 65], torque: [-18, 18], gear: 1, kt: 1, direction: 1, zero: 0}
///     - id: 0x141            # frames with this CAN id (extended: true for 29-bit)
///       joint: knee
///       protocol: linear
///       position: {byte: 0, width: 2, signed: true, endian: little, scale: 0.001, offset: 0}
///       velocity: {byte: 2, width: 2, signed: true, endian: little, scale: 0.01}
///       torque:   {byte: 4, width: 2, signed: true, endian: little, scale: 0.01}
/// (mini_cheetah: `motor_id` is byte 0's expected value, default `id`.)
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "inertial/signal/rejection.hpp"
#include "inertial/transport/can_frame.hpp"

namespace inertial {

enum class MotorProtocol { kMiniCheetah, kLinear };

struct LinearField {
  int byte = 0;
  int width = 2;  ///< 1, 2 or 4 bytes
  bool is_signed = true;
  bool little_endian = true;
  double scale = 1.0, offset = 0.0;
};

struct MotorConfig {
  std::uint32_t can_id = 0;
  bool extended = false;
  int motor_id = -1;  ///< mini_cheetah: byte 0 (-1: can_id)
  std::string joint;
  MotorProtocol protocol = MotorProtocol::kMiniCheetah;
  double p_min = -12.5, p_max = 12.5, v_min = -65.0, v_max = 65.0, t_min = -18.0, t_max = 18.0;
  LinearField position, velocity, torque;
  double gear = 1.0, kt = 1.0, direction = 1.0, zero = 0.0;
};

struct MotorReading {
  double t = 0.0;
  double q = 0.0, qd = 0.0, tau = 0.0;  ///< joint side, SI
};

struct CanConfig {
  double window = 0.002;
  double accel_cutoff_hz = 20.0;
  std::vector<MotorConfig> motors;
};

/// Decodes a frame of motor `m` (its id already matched): Rejection::kNone, or kMalformed for a wrong length, a remote,
/// error or FD frame, or (mini_cheetah) a byte 0 that is not the motor's id.
Rejection DecodeMotorFrame(const MotorConfig& m, const CanFrame& frame, MotorReading* reading,
                           std::string* why = nullptr);

/// The frame motor `m` would send for a joint reading (values saturated at the ranges): for
/// simulated buses and tests.
CanFrame EncodeMotorFrame(const MotorConfig& m, const MotorReading& reading);

}  // namespace inertial
