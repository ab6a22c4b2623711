/// @file log_replay.hpp
/// Recorded logs through the online estimator, exactly as inertiald runs it: an lcm-logger log
/// (lcm::LogFile, event by event, the messages of one channel decoded by joint_message.hpp), the
/// project's joint CSV, or a `candump -l` log of motor-driver frames (can_frame.hpp, assembled into
/// samples by can_joint_assembler.hpp). For each sample the update status; the estimate trajectory as CSV rows
/// and, optionally, as an LCM log of inertial.estimate_t; the throughput.
#pragma once

#include <map>

#include <cstdint>
#include <functional>
#include <optional>
#include <string>

#include "inertial/estimation/online_joint_estimator.hpp"
#include "inertial/runtime/estimation_daemon.hpp"
#include "inertial/transport/can_joint_assembler.hpp"
#include "inertial/formats/joint_csv.hpp"
#include "inertial/transport/joint_message.hpp"

namespace inertial {

struct ReplayOptions {
  std::string channel = "INERTIAL_JOINT_STATE";
  JointMessageFormat format;
  bool realtime = false;            ///< sleep to follow the log's time stamps
  double estimate_period_s = 0.1;   ///< of log time between rows of the estimate CSV / log events
  std::string csv_path;             ///< estimates as CSV (empty: none)
  std::string log_path;             ///< estimates as an LCM log of inertial.estimate_t (empty: none)
  std::string estimate_channel = "INERTIAL_ESTIMATE";
  /// Joint CSV logs: how they are read (e.g. csv.time_scale for stamps in ms or ns).
  JointCsvOptions csv;
  /// Set: the log is a candump log of these motors.
  std::optional<CanConfig> can;
};

struct ReplayResult {
  std::uint64_t events = 0;         ///< log events read (all channels)
  DaemonCounters counters;          ///< of the channel replayed, as inertiald counts them
  double seconds = 0.0;             ///< wall time of the estimation loop
  double samples_per_second = 0.0;  ///< samples given to the estimator per wall second
  std::uint64_t estimate_rows = 0;
  CanCounters can;                  ///< candump logs: the assembler's counters
  std::uint64_t lines_not_frames = 0;  ///< candump logs: lines that are not frames (skipped)
  std::map<std::string, std::uint64_t> channels;  ///< LCM logs: messages per channel, every channel
};

/// Replays `path`: a candump log when options.can is set, else a joint CSV when it ends in ".csv"
/// (joint_csv.hpp contract), else an LCM log. Malformed candump lines are counted
/// (counters.rejected["bad_line"]) and skipped.
/// `on_sample` (optional) sees each sample given to the estimator and its status.
/// @throws std::runtime_error naming the file (cannot open, not an LCM log, cannot write).
ReplayResult ReplayLog(const std::string& path, OnlineJointEstimator* estimator, const ReplayOptions& options,
                       const std::function<void(const JointSample&, UpdateStatus)>& on_sample = {});

}  // namespace inertial
