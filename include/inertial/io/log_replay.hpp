/// @file log_replay.hpp
/// Recorded logs through the online estimator, exactly as inertiald runs it: an lcm-logger log
/// (lcm::LogFile, event by event, the messages of one channel decoded by joint_message.hpp) or the
/// project's joint CSV. For each sample the update status; the estimate trajectory as CSV rows
/// and, optionally, as an LCM log of inertial.estimate_t; the throughput.
#pragma once

#include <cstdint>
#include <functional>
#include <string>

#include "inertial/estimation/online_joint_estimator.hpp"
#include "inertial/io/estimation_daemon.hpp"
#include "inertial/io/joint_message.hpp"

namespace inertial {

struct ReplayOptions {
  std::string channel = "INERTIAL_JOINT_STATE";
  JointMessageFormat format;
  bool realtime = false;            ///< sleep to follow the log's time stamps
  double estimate_period_s = 0.1;   ///< of log time between rows of the estimate CSV / log events
  std::string csv_path;             ///< estimates as CSV (empty: none)
  std::string log_path;             ///< estimates as an LCM log of inertial.estimate_t (empty: none)
  std::string estimate_channel = "INERTIAL_ESTIMATE";
};

struct ReplayResult {
  std::uint64_t events = 0;         ///< log events read (all channels)
  DaemonCounters counters;          ///< of the channel replayed, as inertiald counts them
  double seconds = 0.0;             ///< wall time of the estimation loop
  double samples_per_second = 0.0;  ///< samples given to the estimator per wall second
  std::uint64_t estimate_rows = 0;
};

/// Replays `path`: an LCM log, or a joint CSV when it ends in ".csv" (joint_csv.hpp contract).
/// `on_sample` (optional) sees each sample given to the estimator and its status.
/// @throws std::runtime_error naming the file (cannot open, not an LCM log, cannot write).
ReplayResult ReplayLog(const std::string& path, OnlineJointEstimator* estimator, const ReplayOptions& options,
                       const std::function<void(const JointSample&, UpdateStatus)>& on_sample = {});

}  // namespace inertial
