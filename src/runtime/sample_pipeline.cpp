#include "inertial/runtime/sample_pipeline.hpp"

#include <algorithm>

#include <stdexcept>

#include "inertial/model/rigid_body_regressor.hpp"

namespace inertial {

SamplePipeline::SamplePipeline(OnlineJointEstimator* estimator, double accel_cutoff_hz, double residual_window_s)
    : robot_(estimator),
      preprocessor_(estimator->model().num_dofs(), accel_cutoff_hz),
      residual_(Eigen::VectorXd::Zero(estimator->model().num_dofs())),
      window_sum_(Eigen::VectorXd::Zero(estimator->model().num_dofs())),
      window_rms_(Eigen::VectorXd::Zero(estimator->model().num_dofs())),
      window_s_(residual_window_s) {
  if (!(residual_window_s > 0) || !(accel_cutoff_hz > 0)) {
    throw std::invalid_argument("sample pipeline: the residual window and the acceleration cutoff must be positive");
  }
  // Samples without measured qdd are fitted by momentum rows filtered at the stream's corner.
  estimator->SetMomentumCutoff(accel_cutoff_hz);
}

SamplePipeline::SamplePipeline(OnlineBodyEstimator* estimator, double residual_window_s)
    : body_(estimator),
      preprocessor_(0, 1.0),
      residual_(Eigen::VectorXd::Zero(6)),
      window_sum_(Eigen::VectorXd::Zero(6)),
      window_rms_(Eigen::VectorXd::Zero(6)),
      window_s_(residual_window_s) {
  if (!(residual_window_s > 0)) throw std::invalid_argument("sample pipeline: the residual window must be positive");
}

const RecursiveEstimator& SamplePipeline::estimator() const { return body_ ? body_->estimator() : robot_->estimator(); }
RecursiveEstimator& SamplePipeline::estimator() { return body_ ? body_->estimator() : robot_->estimator(); }

void SamplePipeline::SetLogGains(const Eigen::VectorXd& gains) {
  if (gains.size() == 0) {
    log_gains_.resize(0);
    return;
  }
  if (robot_ == nullptr || gains.size() != robot_->model().num_dofs() || !gains.allFinite() || !(gains.minCoeff() > 0.0)) {
    throw std::invalid_argument("sample pipeline: the log's gains must be one positive number per joint");
  }
  log_gains_ = gains;
}

SamplePipeline::Outcome SamplePipeline::Process(Sample* sample) {
  ++counters_.received;
  Outcome out;
  if (body_) {
    // The residual of the estimate before this sample (samples with an acceleration only; pairs
    // by the midpoint rule have none of their own).
    const BodySample& b = sample->body;
    if (b.has_acceleration) {
      residual_.noalias() = b.wrench - RigidBodyRegressor(b.twist, b.acceleration, b.gravity) * body_->Body().vector();
    } else {
      residual_.setZero();
    }
    out.status = body_->Update(b);
    Account(out.status, b.t);
    return out;
  }
  if (log_gains_.size() != 0 && sample->joint.tau.size() == log_gains_.size()) {
    sample->joint.tau.array() /= log_gains_.array();  // the log's unit to N m (in place: no allocation)
  }
  out.rejection = preprocessor_.Process(&sample->joint);
  if (out.rejection == Rejection::kPriming) {  // only a sample without qdd primes there
    robot_->Prime(sample->joint);  // the estimator's momentum rows start from the same sample
  }
  if (out.rejection != Rejection::kNone) {
    counters_.Reject(out.rejection);
    return out;
  }
  out.status = robot_->Update(sample->joint);
  residual_ = robot_->stream_residual();  // the torque's, not the filtered rows' (online_joint_estimator.hpp)
  Account(out.status, sample->joint.t);
  Reconcile();  // a change resolves the held run at the tick
  return out;
}

void SamplePipeline::Account(UpdateStatus status, double t) {
  counters_.Count(status);
  if (status != UpdateStatus::kAccepted) return;
  if (window_start_ < 0 || t >= window_start_ + window_s_) {
    if (window_count_ > 0) {
      window_rms_ = (window_sum_ / window_count_).cwiseSqrt();
      window_completed_ = true;
    }
    window_sum_.setZero();
    window_count_ = 0;
    window_start_ = t;
  }
  window_sum_ += residual_.cwiseAbs2();
  ++window_count_;
  last_t_ = t;
}

Eigen::VectorXd SamplePipeline::ResidualRms() const {
  if (!window_completed_ && window_count_ > 0) return (window_sum_ / window_count_).cwiseSqrt();
  return window_rms_;
}

SampleCounters TotalCounters(const SampleCounters& decoded, const SampleCounters& processed, std::uint64_t queue_full) {
  SampleCounters t;
  t.received = decoded.received;
  t.accepted = processed.accepted;
  t.buffered = processed.buffered;
  for (int k = 1; k < kNumRejections; ++k) {
    t.rejected[static_cast<std::size_t>(k)] = decoded.rejected[static_cast<std::size_t>(k)] + processed.rejected[static_cast<std::size_t>(k)];
  }
  t.Reject(Rejection::kQueueFull, queue_full);
  return t;
}

bool SamplePipeline::Solve(bool final) {
  if (robot_ == nullptr || robot_->fit() == nullptr) return false;
  if (!final && !robot_->SolveDue()) return false;
  const bool solved = robot_->Solve(final);
  Reconcile();
  return solved;
}

void SamplePipeline::Reconcile() {
  if (robot_ == nullptr || robot_->fit() == nullptr) return;
  const OnlineFit& fit = *robot_->fit();
  const std::uint64_t kept = fit.held_kept() - held_kept_, refused = fit.held_refused() - held_refused_;
  held_kept_ = fit.held_kept();
  held_refused_ = fit.held_refused();
  counters_.buffered -= std::min(counters_.buffered, kept + refused);
  counters_.accepted += kept;
  counters_.Reject(Rejection::kOutlier, refused);
}

}  // namespace inertial
