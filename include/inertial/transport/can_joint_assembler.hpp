/// @file can_joint_assembler.hpp
/// Joint-space samples from several motors' CAN frames: each frame is matched to its motor by
/// identifier (and, for mini_cheetah, byte 0), decoded (motor_codec.hpp), and kept as that joint's
/// latest reading; a tick is complete when every joint of the model has a reading within the
/// window of the newest one, and then becomes one sample at the newest reading's time (qdd by the
/// causal filter). A reading older than the window is dropped and counted late; a motor that
/// reports again before the tick completes replaces its reading, counted superseded. A missing
/// motor is never filled in: its tick simply does not complete.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "inertial/estimation/causal_acceleration.hpp"
#include "inertial/estimation/online_joint_estimator.hpp"
#include "inertial/transport/motor_codec.hpp"
#include "inertial/model/joint_samples.hpp"

namespace inertial {

struct CanCounters {
  std::uint64_t frames = 0;       ///< frames fed
  std::uint64_t unknown_id = 0;   ///< no motor replies with that frame (or not one of the model's joints)
  std::uint64_t malformed = 0;    ///< a motor's frame that did not decode
  std::uint64_t error_frames = 0;
  std::uint64_t late = 0;         ///< readings dropped as older than the window
  std::uint64_t superseded = 0;   ///< readings replaced by a newer one of the same motor
  std::uint64_t ticks = 0;        ///< complete samples produced
  std::uint64_t priming = 0;      ///< complete ticks used only to prime the acceleration filter
};

class CanJointAssembler {
 public:
  /// @throws std::invalid_argument if a DOF of the model has no motor.
  CanJointAssembler(CanConfig config, std::vector<std::string> dof_names);

  /// Feeds one frame; true when it completed a tick (then *sample holds it). *why (optional) says
  /// why a frame was refused.
  bool Feed(const CanFrame& frame, JointSample* sample, std::string* why = nullptr);

  const CanCounters& counters() const { return counters_; }
  const CanConfig& config() const { return config_; }
  /// The motor whose frames these are, or -1.
  int MotorOf(const CanFrame& frame) const;

 private:
  CanConfig config_;
  std::vector<std::string> dofs_;
  std::vector<int> dof_of_motor_;  // -1: a motor of a joint the model does not have
  std::vector<std::optional<MotorReading>> readings_;
  CanCounters counters_;
  CausalAcceleration acceleration_;
};

/// The inverse, for simulated buses: every sample of a joint log as one reply frame per motor of
/// `config` (in config order, the k-th `stagger` seconds after the sample), written as a candump -l
/// log on `interface`. @throws std::invalid_argument if a joint of the log has no motor;
/// std::runtime_error if the file cannot be written.
void WriteMotorCandump(const std::string& path, const std::string& interface, const CanConfig& config,
                       const JointSamples& samples, double stagger = 1e-4);

}  // namespace inertial
