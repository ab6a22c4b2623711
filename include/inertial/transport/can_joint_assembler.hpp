/// @file can_joint_assembler.hpp
/// Joint-space samples from several motors' CAN frames: each frame is matched to its motor by
/// identifier (and, for mini_cheetah, byte 0), decoded (motor_codec.hpp), and kept as that joint's
/// latest reading; a tick is complete when every joint of the model has a reading within the
/// window of the newest one, and then becomes one sample at the newest reading's time (has_qdd
/// false: qdd is the preprocessing stage's, stream_preprocessor.hpp). A reading older than the window is dropped and counted late; a motor that
/// reports again before the tick completes replaces its reading, counted superseded. A missing
/// motor is never filled in: its tick simply does not complete.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "inertial/signal/rejection.hpp"
#include "inertial/transport/motor_codec.hpp"
#include "inertial/model/joint_samples.hpp"

namespace inertial {

class CanJointAssembler {
 public:
  /// @throws std::invalid_argument if a DOF of the model has no motor.
  CanJointAssembler(CanConfig config, std::vector<std::string> dof_names);

  /// Feeds one frame; true when it completed a tick (then *sample holds it). *why (optional) says
  /// why a frame was refused.
  bool Feed(const CanFrame& frame, JointSample* sample, std::string* why = nullptr);

  /// received: frames fed; accepted: ticks completed; rejected, by reason: frames refused
  /// (kErrorFrame, kUnknownId, kMalformed, kLate for a tick not after the previous one) and
  /// readings displaced (kSuperseded, kLate when older than the window). A reading waiting for
  /// the others is neither, so the three need not add up to received.
  const SampleCounters& counters() const { return counters_; }
  /// Why the last Feed gave no sample: the frame's rejection, or kNone (its reading waits for the
  /// other motors' or it completed a tick).
  Rejection last_rejection() const { return last_rejection_; }
  const CanConfig& config() const { return config_; }
  /// The motor whose frames these are, or -1.
  int MotorOf(const CanFrame& frame) const;

 private:
  CanConfig config_;
  std::vector<std::string> dofs_;
  std::vector<int> dof_of_motor_;  // -1: a motor of a joint the model does not have
  std::vector<std::optional<MotorReading>> readings_;
  SampleCounters counters_;
  Rejection last_rejection_ = Rejection::kNone;
  bool ticked_ = false;
  double last_tick_t_ = 0.0;
};

/// The inverse, for simulated buses: every sample of a joint log as one reply frame per motor of
/// `config` (in config order, the k-th `stagger` seconds after the sample), written as a candump -l
/// log on `interface`. @throws std::invalid_argument if a joint of the log has no motor;
/// std::runtime_error if the file cannot be written.
void WriteMotorCandump(const std::string& path, const std::string& interface, const CanConfig& config,
                       const JointSamples& samples, double stagger = 1e-4);

}  // namespace inertial
