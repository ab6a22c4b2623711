/// @file estimation_daemon.hpp
/// inertiald as a library: joint-state messages from an LCM channel (or, for a single body on a
/// wrench sensor, inertial.body_wrench_t messages), the recursive estimator of
/// online_joint_estimator.hpp (online_body_estimator.hpp) on every sample, estimates (inertial.estimate_t) published at a fixed
/// rate, checkpoints of the estimator state, counters of everything.
///
/// Threads: an LCM receiver decodes each message (joint_message.hpp: nothing trusted) and pushes the
/// sample into a bounded queue (a full queue drops the sample and counts it; memory never grows);
/// the estimator thread (Run's caller) pops, updates, publishes and checkpoints. Run returns when
/// `stop` becomes true (e.g. from SIGINT/SIGTERM), after draining the queue, a last publication
/// and a last checkpoint. A checkpoint found at start is restored (same model and estimator, or it
/// is ignored with a warning), so a restart loses only what came after the last one.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <string>

#include "inertial/estimation/online_body_estimator.hpp"
#include "inertial/estimation/online_joint_estimator.hpp"
#include "inertial/transport/can_bus.hpp"
#include "inertial/transport/can_joint_assembler.hpp"
#include "inertial/config/daemon_config.hpp"
#include "inertial/transport/joint_message.hpp"

namespace lcm {
class LCM;
}

namespace inertial {

struct DaemonCounters {
  std::uint64_t received = 0;  ///< messages on the input channel
  std::uint64_t accepted = 0;  ///< samples that updated the estimate
  std::uint64_t dropped = 0;   ///< samples lost to a full queue
  std::uint64_t published = 0;
  std::uint64_t checkpoints = 0;
  std::uint64_t checkpoint_failures = 0;  ///< checkpoints that could not be written
  std::uint64_t publish_failures = 0;     ///< estimates LCM could not send
  std::map<std::string, std::uint64_t> rejected;  ///< by reason (decode, wrong_size, unknown_joint, ...)
  std::uint64_t total_rejected() const;
};

class EstimationDaemon {
 public:
  /// A robot from joint states. @throws std::invalid_argument on bad options, std::runtime_error if
  /// LCM cannot start.
  EstimationDaemon(RobotDynamics model, DaemonOptions options);
  /// One body from inertial.body_wrench_t messages (options.format unused), starting at `prior`.
  EstimationDaemon(const InertialParams& prior, DaemonOptions options);
  /// A robot from its motors' CAN frames (can_joint_assembler.hpp) read from `bus` (filtered to
  /// the motors' identifiers); estimates still go out on LCM.
  EstimationDaemon(RobotDynamics model, DaemonOptions options, CanConfig can, std::unique_ptr<CanBus> bus);
  ~EstimationDaemon();

  /// Runs until `stop` is true; returns 0, or 1 if LCM failed while running.
  int Run(const std::atomic<bool>& stop);

  DaemonCounters counters() const;
  /// A one-paragraph summary of the counters (printed on exit).
  std::string CountersText() const;
  /// The robot's estimator (robot mode only).
  const OnlineJointEstimator& estimator() const { return *estimator_; }
  /// The body's estimator (single-body mode only), or null.
  const OnlineBodyEstimator* body_estimator() const { return body_.get(); }
  /// Either mode's recursive estimator.
  const RecursiveEstimator& recursive_estimator() const;
  /// The daemon's LCM instance (LCM publishes from any thread): with memq:// the only way in.
  lcm::LCM& lcm();
  bool restored_from_checkpoint() const { return restored_; }
  /// Robot mode: `sink` gets the estimator at exit (after the last sample) and, while running,
  /// whenever *request is set (it is cleared), e.g. from SIGUSR1: inertiald --write-urdf. A sink's
  /// exception is logged; the daemon keeps running.
  void set_model_sink(std::function<void(const OnlineJointEstimator&)> sink, std::atomic<bool>* request) {
    model_sink_ = std::move(sink);
    model_request_ = request;
  }
  /// Where log lines go (default stderr).
  void set_log_sink(std::function<void(const std::string&)> sink) { log_sink_ = std::move(sink); }

 private:
  struct Impl;
  struct Sample;  // what the queue holds: a joint sample or a body sample
  void Start(int num_channels);
  void Log(LogLevel level, const std::string& text) const;
  /// What the daemon cannot do is said once: the first time `problem` occurs, true (log it, at warn
  /// or error); after that false (log at debug level: the counters carry the count) until
  /// Recovered(problem). Thread-safe.
  bool FirstTime(const std::string& problem);
  /// `problem` no longer occurs: true if it had (log that once), and it will be said again if it recurs.
  bool Recovered(const std::string& problem);
  void Process(const Sample& sample);
  void Account(UpdateStatus status, double t, const Eigen::VectorXd& residual);
  void Publish(std::int64_t utime);
  void Checkpoint();
  std::string Description() const;

  DaemonOptions options_;
  std::unique_ptr<OnlineJointEstimator> estimator_;
  std::unique_ptr<OnlineBodyEstimator> body_;
  std::unique_ptr<Impl> impl_;
  mutable std::mutex counters_mutex_, log_mutex_, problems_mutex_;
  std::set<std::string> problems_;  // FirstTime
  DaemonCounters counters_;
  bool restored_ = false;
  std::function<void(const std::string&)> log_sink_;
  std::function<void(const OnlineJointEstimator&)> model_sink_;
  std::atomic<bool>* model_request_ = nullptr;
  void WriteModel();
  // Residual window.
  Eigen::VectorXd window_sum_, window_rms_;
  double window_start_ = -1.0, last_t_ = 0.0;
  int window_count_ = 0;
  bool window_completed_ = false;
};

/// What a robot estimator's checkpoint says of its model ("gauss_newton estimator; joints ...;
/// parameters ..."): a checkpoint is restored only into an estimator with the same description.
std::string CheckpointDescription(const OnlineJointEstimator& estimator);

/// The estimate message of the single-body estimator (one body `name`; channels mx .. fz).
std::vector<std::uint8_t> EncodeBodyEstimate(const OnlineBodyEstimator& estimator, const std::string& name,
                                             std::int64_t utime, const Eigen::VectorXd& residual_rms,
                                             double residual_window, const DaemonCounters& counters);

/// The estimate message of an online estimator (bodies, effects, residual RMS, counters).
std::vector<std::uint8_t> EncodeEstimate(const OnlineJointEstimator& estimator, std::int64_t utime,
                                         const Eigen::VectorXd& residual_rms, double residual_window,
                                         const DaemonCounters& counters);

}  // namespace inertial
