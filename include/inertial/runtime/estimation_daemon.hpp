/// @file estimation_daemon.hpp
/// inertiald as a library: the threaded driver of the sample pipeline. Source: joint-state
/// messages from an LCM channel, inertial.body_wrench_t messages of a single body on a wrench
/// sensor, or a robot's motor frames from a CAN bus; sinks: estimates (inertial.estimate_t)
/// published at a fixed rate, residuals, checkpoints of the estimator state, a model file.
///
/// Threads (issue 37: the loop never waits):
/// - the receiver drains the source (LCM's handle, or the CAN bus) and does nothing else: it decodes
///   each input (sample_decoder.hpp: nothing trusted), notes its time stamp (stream_gap_counter.hpp:
///   samples lost before the daemon, seen as gaps) and pushes the sample into a bounded queue (a
///   full queue drops the sample and counts it, kQueueFull; memory never grows); its log lines go
///   to the writer through a slot ring;
/// - the estimator thread (Run's caller) pops into the pipeline (sample_pipeline.hpp: preprocess,
///   estimator, accounting; the same code replay runs, log_replay.hpp) and only hands over: a
///   residual's numbers, a payload event, and at their periods the requests for an estimate, a
///   diagnosis, a checkpoint, a model file. It never publishes, writes a file or syncs one;
/// - the publisher thread takes the estimator's hand-overs from a ring of preallocated slots
///   (slot_ring.hpp; a full ring drops the item, counted dropped at the sink) and publishes on LCM
///   (an estimate is encoded there, from the estimator's state under its lock);
/// - the writer thread writes checkpoints and model files (fsyncs included): a request still
///   pending when the next comes is coalesced with it (the latest state wins; counted);
/// - the solver (the online fit) and the diagnosis have threads of their own.
/// Run returns when
/// `stop` becomes true (e.g. from SIGINT/SIGTERM), after draining the queue and the sinks, a last
/// publication and a last checkpoint. A checkpoint found at start is restored (same model and
/// estimator, or it is ignored with a warning), so a restart loses only what came after the last one.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <string>

#include "inertial/config/daemon_config.hpp"
#include "inertial/estimation/online/online_body_estimator.hpp"
#include "inertial/estimation/online/online_joint_estimator.hpp"
#include "inertial/diagnosis/payload_event.hpp"
#include "inertial/runtime/estimate_message.hpp"
#include "inertial/runtime/sample_decoder.hpp"
#include "inertial/runtime/sample_pipeline.hpp"
#include "inertial/diagnosis/stream_diagnosis.hpp"
#include "inertial/transport/can_bus.hpp"

namespace lcm {
class LCM;
}

namespace inertial {

/// The daemon's counters: the pipeline's as a whole (TotalCounters, sample_pipeline.hpp: inputs
/// received, samples accepted, rejections of every stage by reason, kQueueFull for samples dropped
/// by a full queue) and its sinks'.
struct DaemonCounters {
  SampleCounters samples;
  std::uint64_t published = 0;
  std::uint64_t checkpoints = 0;
  std::uint64_t checkpoint_failures = 0;  ///< checkpoints that could not be written
  std::uint64_t publish_failures = 0;     ///< estimates LCM could not send
  std::uint64_t diagnoses = 0;            ///< diagnosis_t messages published
  std::uint64_t diagnosis_dropped = 0;    ///< samples the diagnosis's ring had no room for
  std::uint64_t payload_events = 0;       ///< payload events published
  /// Samples lost before the daemon: gaps in the stream's time stamps (stream_gap_counter.hpp), not
  /// inputs; apart from samples.rejected[kQueueFull], the samples dropped inside the daemon.
  std::uint64_t lost = 0;
  std::uint64_t gaps = 0;                 ///< the gaps those were lost in
  double longest_gap_s = 0.0;             ///< the longest gap [s]
  double median_interval_s = 0.0;         ///< the stream's median sample interval [s] (0 before it is known)
  /// Dropped at the sink: hand-overs the publisher's ring had no room for (it was behind).
  std::uint64_t residuals_dropped = 0;
  std::uint64_t messages_dropped = 0;     ///< estimates, diagnoses and payload events
  std::uint64_t log_lines_dropped = 0;    ///< the receiver's log lines
  /// Checkpoint and model requests merged into one still pending (the latest state was written).
  std::uint64_t checkpoints_coalesced = 0;
  std::uint64_t models_coalesced = 0;
};

class EstimationDaemon {
 public:
  /// A robot from joint states. @throws std::invalid_argument on bad options, StateFileError
  /// (estimator_state_file.hpp) if options.checkpoint names a file that cannot be restored or a place
  /// that cannot take one, std::runtime_error if LCM cannot start.
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
  /// The robot's estimator, or null for a single body.
  const OnlineJointEstimator* robot_estimator() const { return robot_.get(); }
  /// The body's estimator, or null for a robot.
  const OnlineBodyEstimator* body_estimator() const { return body_.get(); }
  /// The online diagnosis (robot mode with a diagnosis channel), else null.
  StreamDiagnosis* diagnosis() const { return diagnosis_.get(); }
  /// Either mode's recursive estimator.
  const RecursiveEstimator& recursive_estimator() const { return pipeline_->estimator(); }
  /// The daemon's LCM instance (LCM publishes from any thread): with memq:// the only way in.
  lcm::LCM& lcm();
  bool restored_from_checkpoint() const { return restored_; }
  /// Robot mode: `sink` gets the estimator at exit (after the last sample) and, while running,
  /// whenever *request is set (it is cleared), e.g. from SIGUSR1: inertiald --write-urdf. It is
  /// called under the estimator's lock, on the writer thread: it takes what it needs (a snapshot)
  /// and returns the write, which runs after the lock is released. A sink's exception is logged;
  /// the daemon keeps running.
  using ModelSink = std::function<std::function<void()>(const OnlineJointEstimator&)>;
  void set_model_sink(ModelSink sink, std::atomic<bool>* request) {
    model_sink_ = std::move(sink);
    model_request_ = request;
  }
  /// A test's stand-in for a slow sink: called by the publisher thread before each hand-over it
  /// delivers (e.g. one that blocks until released). Set before Run.
  void set_publisher_hook_for_tests(std::function<void()> hook) { publisher_hook_ = std::move(hook); }
  /// Where log lines go (default stderr).
  void set_log_sink(std::function<void(const std::string&)> sink) { log_sink_ = std::move(sink); }

 private:
  struct Impl;
  EstimationDaemon(DaemonOptions options, SampleDecoder decoder, std::unique_ptr<OnlineJointEstimator> robot,
                   std::unique_ptr<OnlineBodyEstimator> body, std::unique_ptr<CanBus> bus);
  void RestoreCheckpoint();
  void Log(LogLevel level, const std::string& text) const;
  /// What the daemon cannot do is said once: the first time `problem` occurs, true (log it, at warn
  /// or error); after that false (log at debug level: the counters carry the count) until
  /// Recovered(problem). Thread-safe.
  bool FirstTime(const std::string& problem);
  /// `problem` no longer occurs: true if it had (log that once), and it will be said again if it recurs.
  bool Recovered(const std::string& problem);
  void Process(Sample* sample);
  /// The estimate now (encoded under the estimator's lock), published. Publisher thread (or Run at exit).
  void Publish();
  /// The diagnosis's latest judgement on its channel, and a new one asked for (robot mode).
  void PublishDiagnosis(std::int64_t utime);
  struct Outgoing;
  /// Publisher thread: one hand-over of the estimator thread's.
  void Deliver(const Outgoing& item);
  /// Estimator thread: asks the publisher for an estimate or a diagnosis (false if its ring is full: counted).
  bool Request(int kind, std::int64_t utime);
  /// At exit: the judgement of everything observed, published and logged.
  void FinalDiagnosis(std::int64_t utime);
  void Checkpoint();
  void WriteModel();
  // Run's threads and its end: the receiver only drains the source (decode, note the time, push);
  // the publisher and the writer take the estimator thread's hand-overs; the solver re-solves the
  // online fit from snapshots; FinishRun solves, publishes, checkpoints and writes the model last.
  void ReceiveLoop(const std::atomic<bool>& stop, std::atomic<bool>& failed);
  void PublishLoop(const std::atomic<bool>& stop);
  void WriteLoop(const std::atomic<bool>& stop);
  void SolveLoop(const std::atomic<bool>& stop);
  void FinishRun(std::int64_t utime);
  /// The estimator thread: pops, processes, hands over; publications, checkpoints and model files
  /// asked for on time. Nothing here publishes, writes or syncs.
  void EstimateLoop(const std::atomic<bool>& stop, const std::atomic<bool>& receiver_failed, Sample* sample);
  /// The last sample's time [us], under the estimator's lock.
  std::int64_t LastUtime() const;

  DaemonOptions options_;
  std::unique_ptr<OnlineJointEstimator> robot_;
  std::unique_ptr<OnlineBodyEstimator> body_;
  std::unique_ptr<SamplePipeline> pipeline_;  // touched by the estimator thread, under process_mutex_
  std::unique_ptr<StreamDiagnosis> diagnosis_;  // robot mode with a diagnosis channel; its own thread
  std::uint64_t changes_seen_ = 0;            // the estimator's detected changes, under process_mutex_
  std::unique_ptr<PayloadEventDetector> payload_events_;  // robot mode with a payload channel, under process_mutex_
  std::unique_ptr<Impl> impl_;
  mutable std::mutex process_mutex_, sinks_mutex_, log_mutex_, problems_mutex_;
  std::set<std::string> problems_;  // FirstTime
  std::uint64_t published_ = 0, checkpoints_ = 0, checkpoint_failures_ = 0, publish_failures_ = 0;  // sinks_mutex_
  std::uint64_t diagnoses_ = 0, payload_events_published_ = 0;  // sinks_mutex_
  std::vector<std::string> unexcited_;  // the latest excitation judgement's, for estimate_t; sinks_mutex_
  std::string last_excitation_text_;    // the publisher thread's
  bool restored_ = false;
  std::function<void(const std::string&)> log_sink_;
  ModelSink model_sink_;
  std::function<void()> publisher_hook_;
  std::atomic<bool>* model_request_ = nullptr;
};

}  // namespace inertial
