/// @file sample_pipeline.hpp
/// The estimating half of the one sample pipeline, source -> decode (sample_decoder.hpp) ->
/// preprocess -> estimator -> sinks, shared by inertiald (a thread pops the queue into it) and
/// replay (a loop feeds it), for a robot and for a single body alike:
/// - preprocess (robot mode): stream_preprocessor.hpp (time order, qdd derived where not measured,
///   for the consumers that want an acceleration);
/// - estimator: OnlineJointEstimator or OnlineBodyEstimator, one update per sample; where qdd was
///   not measured the robot's estimator fits momentum rows (momentum_rows.hpp), not the derived qdd;
/// - accounting: SampleCounters (rejection.hpp) of every outcome, and the residual window (RMS per
///   channel over windows of residual_window_s of sample time, of accepted samples: the residual
///   of the estimate before the sample, i.e. its prediction error);
/// - sinks get the state from here: the estimate message (estimate_message.hpp), the residual.
/// Process never throws and never allocates after the first sample. Not thread-safe: one thread.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "inertial/estimation/online/online_body_estimator.hpp"
#include "inertial/estimation/online/online_joint_estimator.hpp"
#include "inertial/signal/rejection.hpp"
#include "inertial/signal/stream_preprocessor.hpp"
#include "inertial/runtime/sample.hpp"

namespace inertial {

class SamplePipeline {
 public:
  /// A robot: samples are preprocessed (qdd low-passed at accel_cutoff_hz where not measured) and
  /// given to *estimator, which must outlive the pipeline; its momentum rows are filtered at
  /// accel_cutoff_hz too (OnlineJointEstimator::SetMomentumCutoff). @throws std::invalid_argument if
  /// residual_window_s or accel_cutoff_hz is not positive.
  SamplePipeline(OnlineJointEstimator* estimator, double accel_cutoff_hz, double residual_window_s);
  /// A single body: samples go to *estimator as they are.
  SamplePipeline(OnlineBodyEstimator* estimator, double residual_window_s);

  /// What became of one sample: refused by the preprocessing stage (rejection set, status
  /// unused), or given to the estimator (rejection kNone, status its outcome).
  struct Outcome {
    Rejection rejection = Rejection::kNone;
    UpdateStatus status = UpdateStatus::kAccepted;
    bool accepted() const { return rejection == Rejection::kNone && status == UpdateStatus::kAccepted; }
  };
  /// Per DOF, the gain of the logged torque (gain@joint of the model file): every robot sample's
  /// tau is divided by it before anything else. Empty: the log is in N m. @throws
  /// std::invalid_argument if not num_dofs positive finite numbers.
  void SetLogGains(const Eigen::VectorXd& gains);
  /// One decoded sample through preprocessing and the estimator (*sample is completed in place).
  Outcome Process(Sample* sample);
  /// For drivers that solve in line (replay): re-solves the robot's objective (gauss_newton,
  /// online_fit.hpp) warm-started if it is due; with final, now and from identify's start (the
  /// estimate of the whole log: identify's fit). Allocates; not for a real-time loop (inertiald
  /// solves on a thread of its own). True if the estimate changed.
  bool Solve(bool final = false);
  /// The online fit's held samples (counted buffered here when held) that solves have resolved
  /// since the last call are moved to accepted or outlier (OnlineFit::held_kept / held_refused).
  /// Process and Solve call it; a driver that adopts solutions itself (inertiald) calls it after.
  void Reconcile();

  /// received: samples given to Process; accepted, buffered, rejected by reason.
  const SampleCounters& counters() const { return counters_; }
  /// The RMS residual per channel over the last complete window; before one is complete, over
  /// the accepted samples so far (zeros before any).
  Eigen::VectorXd ResidualRms() const;
  double residual_window_s() const { return window_s_; }
  /// The time of the last accepted sample (0 before any).
  double last_time() const { return last_t_; }
  /// The residual of the last sample given to the estimator (measured - predicted by the estimate
  /// before the sample, per channel). Where qdd was not measured, the estimator fits filtered
  /// momentum rows, whose residual is of the filtered torque; this one is the estimator's
  /// stream_residual(), of the torque low-passed as the derived qdd is, which the diagnosis and
  /// the residual channel expect (their features are of the sample).
  const Eigen::VectorXd& last_residual() const { return residual_; }

  bool body_mode() const { return body_ != nullptr; }
  /// Robot mode's estimator, or null.
  const OnlineJointEstimator* robot() const { return robot_; }
  /// Body mode's estimator, or null.
  const OnlineBodyEstimator* body() const { return body_; }
  const RecursiveEstimator& estimator() const;
  RecursiveEstimator& estimator();
  /// Channels of the residual: the robot's DOFs, or mx, my, mz, fx, fy, fz.
  int num_channels() const { return static_cast<int>(window_sum_.size()); }

 private:
  void Account(UpdateStatus status, double t);

  OnlineJointEstimator* robot_ = nullptr;
  OnlineBodyEstimator* body_ = nullptr;
  StreamPreprocessor preprocessor_;
  SampleCounters counters_;
  Eigen::VectorXd residual_, window_sum_, window_rms_;
  Eigen::VectorXd log_gains_;  ///< empty: tau in N m
  double window_s_, window_start_ = -1.0, last_t_ = 0.0;
  int window_count_ = 0;
  std::uint64_t held_kept_ = 0, held_refused_ = 0;  ///< the fit's, as of the last Reconcile
  bool window_completed_ = false;
};

/// The counters of the pipeline as a whole, from its stages': received from the decoder (inputs:
/// messages, frames, lines), accepted and buffered from the estimator stage, rejections of every
/// stage summed (the decoder's, the queue's kQueueFull, the preprocessor's and the estimator's).
SampleCounters TotalCounters(const SampleCounters& decoded, const SampleCounters& processed,
                             std::uint64_t queue_full = 0);

}  // namespace inertial
