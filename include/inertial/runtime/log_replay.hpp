/// @file log_replay.hpp
/// Recorded logs through the sample pipeline, exactly as inertiald runs it (replay is the loop
/// driver of the same stages: sample_decoder.hpp, sample_pipeline.hpp, estimate_message.hpp):
/// an lcm-logger log (lcm::LogFile, event by event, the messages of one channel, joint states or a
/// single body's wrenches), the project's joint CSV, or a `candump -l` log of motor-driver frames
/// (can_frame.hpp). For each sample the outcome; the estimate trajectory as CSV rows and,
/// optionally, as an LCM log of inertial.estimate_t; the throughput.
#pragma once

#include <map>

#include <cstdint>
#include <functional>
#include <optional>
#include <string>

#include "inertial/estimation/online/online_body_estimator.hpp"
#include "inertial/estimation/online/online_joint_estimator.hpp"
#include "inertial/formats/joint_csv.hpp"
#include "inertial/runtime/sample.hpp"
#include "inertial/runtime/sample_pipeline.hpp"
#include "inertial/transport/joint_message.hpp"
#include "inertial/transport/motor_codec.hpp"

namespace inertial {

struct ReplayOptions {
  std::string channel = "INERTIAL_JOINT_STATE";
  JointMessageFormat format;
  bool realtime = false;            ///< sleep to follow the log's time stamps
  double estimate_period_s = 0.1;   ///< of log time between rows of the estimate CSV / log events
  double residual_window_s = 1.0;   ///< the residual RMS window of the estimates (as inertiald's)
  std::string csv_path;             ///< estimates as CSV (empty: none)
  std::string log_path;             ///< estimates as an LCM log of inertial.estimate_t (empty: none)
  std::string estimate_channel = "INERTIAL_ESTIMATE";
  /// Joint CSV logs: how they are read (e.g. csv.time_scale for stamps in ms or ns).
  JointCsvOptions csv;
  /// Set: the log is a candump log of these motors.
  std::optional<CanConfig> can;
  /// Per DOF: the gain of the logged torques (gain@joint of the model file); empty: N m.
  Eigen::VectorXd log_gains;
};

struct ReplayResult {
  std::uint64_t events = 0;         ///< log events read (all channels; lines of a candump log)
  /// Of the channel (or frames) replayed, as inertiald counts them (TotalCounters of the stages).
  SampleCounters counters;
  double seconds = 0.0;             ///< wall time of the estimation loop
  double samples_per_second = 0.0;  ///< samples given to the estimator per wall second
  std::uint64_t estimate_rows = 0;
  std::uint64_t samples = 0;        ///< samples decoded and given to the pipeline
  std::uint64_t lines_not_frames = 0;  ///< candump logs: lines that are not frames (skipped)
  std::map<std::string, std::uint64_t> channels;  ///< LCM logs: messages per channel, every channel
};

/// Replays `path` for a robot: a candump log when options.can is set, else a joint CSV when it
/// ends in ".csv" (joint_csv.hpp contract; differentiated as a log, log_differentiation.hpp), else
/// an LCM log of joint states. Malformed candump lines are counted (kBadLine) and skipped.
/// `on_sample` (optional) sees each sample the pipeline processed and its outcome.
/// @throws std::runtime_error naming the file (cannot open, not an LCM log, cannot write).
ReplayResult ReplayLog(const std::string& path, OnlineJointEstimator* estimator, const ReplayOptions& options,
                       const std::function<void(const Sample&, SamplePipeline::Outcome)>& on_sample = {});

/// Replays an LCM log of inertial.body_wrench_t messages on options.channel for a single body.
ReplayResult ReplayBodyLog(const std::string& path, OnlineBodyEstimator* estimator, const ReplayOptions& options,
                           const std::function<void(const Sample&, SamplePipeline::Outcome)>& on_sample = {});

}  // namespace inertial
