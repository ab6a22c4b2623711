/// @file stream_diagnosis.hpp
/// The online diagnosis (diagnosis/online_diagnosis.hpp) beside the estimator of inertiald and of
/// replay, off the estimator's hot path (the realtime_tools pattern: the real-time loop never
/// blocks and never computes what can wait).
///
/// The estimator's thread calls Observe() after each sample it accepted: the sample's state and the
/// estimator's residual before the update are copied into a ring of fixed capacity (allocated once;
/// a full ring drops the sample and counts it) under an uncontended mutex, with no wake-up call. A
/// worker thread drains the ring every few milliseconds into OnlineDiagnosis::Add and, when asked
/// (RequestEvaluation, with the estimator's bodies for the payload candidates), judges the
/// candidates and keeps the result for Latest(). With threaded = false (replay) Observe() adds
/// directly and Evaluate() judges at once, so a replay's result does not depend on scheduling.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

#include "inertial/diagnosis/excitation_monitor.hpp"
#include "inertial/diagnosis/online_diagnosis.hpp"
#include "inertial/estimation/online/online_joint_estimator.hpp"

namespace inertial {

struct StreamDiagnosisOptions {
  OnlineDiagnosisOptions diagnosis;
  bool threaded = true;
  /// Samples the ring holds between two drains (the worker drains every 5 ms: 4096 is 4 s at 1 kHz).
  int capacity = 4096;
  /// The excitation monitor (excitation_monitor.hpp): the information of every excitation_decimation-th
  /// sample, weighted by it, over excitation.window_seconds and since start. Off without a prior.
  ExcitationOptions excitation;
  int excitation_decimation = 4;
  Eigen::VectorXd measurement_sigma;  ///< per DOF [N m]
  Eigen::MatrixXd prior_covariance;   ///< of x at the start (the estimator's initial P); empty: no monitor
};

/// What the worker judged: the missing effects and, with a monitor, the excitation.
struct StreamJudgement {
  OnlineDiagnosisResult diagnosis;
  std::optional<ExcitationReport> excitation;
};

/// StreamDiagnosisOptions for `estimator`'s model: the measurement sigma and the prior covariance of
/// a fresh Gauss-Newton estimator with `options` (the information's reference, whatever the kind).
StreamDiagnosisOptions StreamDiagnosisOptionsFor(const RobotDynamics& model, const OnlineEstimatorOptions& options);

/// The estimator's bodies as OnlineBodyStates (allocates: call it at publication time, not per tick).
std::vector<OnlineBodyState> BodyStatesOf(const OnlineJointEstimator& estimator);

class StreamDiagnosis {
 public:
  /// @throws std::invalid_argument for bad options (as OnlineDiagnosis; capacity < 1).
  StreamDiagnosis(const RobotDynamics& model, const StreamDiagnosisOptions& options);
  ~StreamDiagnosis();
  StreamDiagnosis(const StreamDiagnosis&) = delete;
  StreamDiagnosis& operator=(const StreamDiagnosis&) = delete;

  /// One accepted sample and the estimator's residual before it updated on it. Never allocates,
  /// never blocks on the worker, never throws.
  void Observe(const JointSample& sample, const Eigen::VectorXd& residual) noexcept;
  /// The system changed (the estimator's change detector fired): the statistics start again, in
  /// order (the samples observed before are judged with the old system). Never allocates.
  void Reset();
  /// Threaded: asks the worker to judge the candidates with `bodies` (and the excitation at the
  /// estimator's parameters x) once it has added what was observed so far; the result appears in
  /// Latest(). Unthreaded: judges now.
  void RequestEvaluation(std::vector<OnlineBodyState> bodies, Eigen::VectorXd x);
  /// The latest judgement (none before the first).
  std::optional<StreamJudgement> Latest() const;
  /// Judges now, after every observed sample is added (the end of a replay or of the daemon).
  StreamJudgement EvaluateNow(const std::vector<OnlineBodyState>& bodies, const Eigen::VectorXd& x);
  /// Entries in the ring not drained yet.
  std::size_t pending() const {
    std::lock_guard<std::mutex> lock(ring_mutex_);
    return size_;
  }
  /// Samples dropped because the ring was full.
  std::uint64_t dropped() const { return dropped_.load(); }

 private:
  struct Entry {
    bool reset = false;   // the statistics start again before this entry
    bool sample = true;   // false: a reset marker only
    double t = 0.0;
    Eigen::VectorXd q, qd, qdd, tau, residual;
  };
  /// Copies the sample into *e (false, nothing copied, if its sizes are not the model's).
  static bool Fill(const JointSample& s, const Eigen::VectorXd& residual, Entry* e);
  void Drain();
  void Work();
  void AddToDiagnosis(const Entry& e);  // under diagnosis_mutex_
  StreamJudgement Judge(const std::vector<OnlineBodyState>& bodies, const Eigen::VectorXd& x) const;

  OnlineDiagnosis diagnosis_;  // under diagnosis_mutex_, with the members below
  std::optional<ExcitationMonitor> excitation_;
  TreeWorkspace workspace_;
  Eigen::MatrixXd features_;
  std::uint64_t observed_ = 0;
  StreamDiagnosisOptions options_;
  std::vector<Entry> ring_;    // under ring_mutex_
  std::size_t head_ = 0, size_ = 0;
  Entry scratch_;              // the worker's copy
  mutable std::mutex ring_mutex_, diagnosis_mutex_, result_mutex_, drain_mutex_;
  std::condition_variable wake_;
  std::optional<std::vector<OnlineBodyState>> request_;  // under result_mutex_
  Eigen::VectorXd request_x_;                            // under result_mutex_
  bool reset_pending_ = false;                            // under ring_mutex_: a reset the full ring could not hold
  std::optional<StreamJudgement> latest_;                // under result_mutex_
  std::atomic<std::uint64_t> dropped_{0};
  std::atomic<bool> stop_{false};
  std::thread worker_;
};

}  // namespace inertial
