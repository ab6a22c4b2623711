/// @file sample_decoder.hpp
/// The decoding stage of the sample pipeline: what a source delivers, into Samples (sample.hpp).
/// One class for every source, so inertiald and replay decode alike:
/// - LCM messages (live, or events of an lcm-logger log) of joint states, in a message format
///   (joint_message.hpp), or of a single body's twist and wrench (body_message.hpp);
/// - CAN frames (live from a bus, or lines of a `candump -l` log) of a robot's motors, assembled
///   into ticks (can_joint_assembler.hpp).
/// Nothing is trusted; every input is counted (SampleCounters: received, accepted = samples given,
/// rejected by reason, rejection.hpp). Decoders only decode: derivatives are the preprocessing
/// stage's (stream_preprocessor.hpp), whose cutoff the decoder carries from its configuration.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "inertial/signal/rejection.hpp"
#include "inertial/runtime/sample.hpp"
#include "inertial/transport/can_bus.hpp"
#include "inertial/transport/can_joint_assembler.hpp"
#include "inertial/transport/joint_message.hpp"

namespace inertial {

class SampleDecoder {
 public:
  /// Joint-state messages of `format` for a robot with these DOFs. @throws std::invalid_argument
  /// (joint_message.hpp).
  static SampleDecoder JointMessages(JointMessageFormat format, std::vector<std::string> dof_names);
  /// inertial.body_wrench_t messages of one body.
  static SampleDecoder BodyWrenches();
  /// Motor frames of `config` for a robot with these DOFs. @throws std::invalid_argument
  /// (can_joint_assembler.hpp).
  static SampleDecoder CanFrames(CanConfig config, std::vector<std::string> dof_names);

  /// One LCM message (joint or body mode); true if *sample now holds a sample. recv_utime stands
  /// for the time when the format has none. *why (optional) says why not.
  bool DecodeMessage(const void* data, std::size_t size, std::int64_t recv_utime, Sample* sample,
                     std::string* why = nullptr);
  /// One CAN frame (CAN mode); true if it completed a tick, now in *sample.
  bool DecodeFrame(const CanFrame& frame, Sample* sample, std::string* why = nullptr);
  /// A frame's line of a candump log that does not parse: counted (received, kBadLine).
  void CountBadLine();

  SampleCounters counters() const;
  /// Why the last input gave no sample (kNone: a CAN reading waits for the other motors).
  Rejection last_rejection() const { return last_; }
  bool body_mode() const { return mode_ == Mode::kBody; }
  bool can_mode() const { return mode_ == Mode::kCan; }
  /// The low-pass cutoff the preprocessing stage derives qdd with (from the format or the motors).
  double accel_cutoff_hz() const;
  /// CAN mode: the motors' identifiers (to filter a bus on).
  std::vector<CanId> can_ids() const;

 private:
  enum class Mode { kJoint, kBody, kCan };
  explicit SampleDecoder(Mode mode) : mode_(mode) {}
  Mode mode_;
  std::optional<JointMessageDecoder> joint_;
  std::optional<CanJointAssembler> can_;
  SampleCounters counters_;  // joint and body modes (CAN: the assembler's, plus bad lines)
  std::uint64_t bad_lines_ = 0;
  Rejection last_ = Rejection::kNone;
};

}  // namespace inertial
