#include "inertial/diagnosis/stream_diagnosis.hpp"

#include "inertial/estimation/fit_uncertainty.hpp"

#include <chrono>
#include <stdexcept>

namespace inertial {

std::vector<OnlineBodyState> BodyStatesOf(const OnlineJointEstimator& estimator) {
  if (const OnlineFit* fit = estimator.fit()) {
    // The online fit: the bodies' uncertainty of the batch objective at its last solve, as the
    // batch diagnosis takes it (fit_uncertainty.hpp; undetermined directions left out).
    std::vector<OnlineBodyState> states = OnlineBodyStates(estimator.model(), fit->parameters(), {}, false);
    if (const auto& u = fit->uncertainty()) {
      for (size_t e = 0; e < states.size(); ++e) {
        states[e].pi_covariance = u->body_pi_covariance[e];
        states[e].std = u->bodies[e];
      }
    }
    return states;
  }
  return OnlineBodyStates(estimator.model(), estimator.estimator().parameters(), estimator.estimator().Covariance(),
                          estimator.kind() == EstimatorKind::kLinearRls);
}

StreamDiagnosisOptions StreamDiagnosisOptionsFor(const RobotDynamics& model, const OnlineEstimatorOptions& options) {
  StreamDiagnosisOptions o;
  OnlineEstimatorOptions ekf = options;  // the prior covariance of x the EKF starts from
  ekf.kind = EstimatorKind::kEkf;
  const OnlineJointEstimator fresh(model, Eigen::VectorXd::Zero(model.num_parameters()), ekf);
  o.prior_covariance = fresh.estimator().Covariance();
  o.measurement_sigma = Eigen::VectorXd::Constant(model.num_dofs(), options.measurement_sigma);
  return o;
}

StreamDiagnosis::StreamDiagnosis(const RobotDynamics& model, const StreamDiagnosisOptions& options)
    : diagnosis_(model, options.diagnosis), workspace_(model.MakeWorkspace()),
      features_(Eigen::MatrixXd::Zero(model.num_dofs(), model.num_features())), options_(options) {
  if (options.capacity < 1 || options.excitation_decimation < 1) {
    throw std::invalid_argument("stream diagnosis: the ring's capacity and the excitation's decimation must be at least 1");
  }
  if (options.prior_covariance.size() > 0) {
    excitation_.emplace(model, options.measurement_sigma, options.prior_covariance, options.excitation);
  }
  const int n = model.num_dofs();
  Entry prototype;
  prototype.q = prototype.qd = prototype.qdd = prototype.tau = prototype.residual = Eigen::VectorXd::Zero(n);
  scratch_ = prototype;
  if (options.threaded) {
    ring_.assign(static_cast<std::size_t>(options.capacity), prototype);
    worker_ = std::thread([this] { Work(); });
  }
}

StreamDiagnosis::~StreamDiagnosis() {
  stop_ = true;
  wake_.notify_all();
  if (worker_.joinable()) worker_.join();
}

void StreamDiagnosis::AddToDiagnosis(const Entry& e) {
  diagnosis_.Add(e.t, e.q, e.qd, e.qdd, e.tau, e.residual);
  // The excitation monitor's information costs O(F^2 m) a sample (3.5 us on the 7-DOF arm): every
  // k-th sample, weighted by k, carries the same information to first order on a trajectory that
  // changes little over k samples.
  if (excitation_ && observed_++ % static_cast<std::uint64_t>(options_.excitation_decimation) == 0 &&
      e.q.allFinite() && e.qd.allFinite() && e.qdd.allFinite()) {
    diagnosis_.model().Features(e.q, e.qd, e.qdd, &workspace_, features_);
    excitation_->Add(e.t, features_, options_.excitation_decimation);
  }
}

bool StreamDiagnosis::Fill(const JointSample& s, const Eigen::VectorXd& residual, Entry* e) {
  const Eigen::Index n = e->q.size();
  if (s.q.size() != n || s.qd.size() != n || s.qdd.size() != n || s.tau.size() != n || residual.size() != n) {
    return false;  // not a sample of this model: OnlineDiagnosis::Add would ignore it too
  }
  e->reset = false;
  e->sample = true;
  e->t = s.t;
  e->q = s.q;  // sizes equal: no allocation
  e->qd = s.qd;
  e->qdd = s.qdd;
  e->tau = s.tau;
  e->residual = residual;
  return true;
}

void StreamDiagnosis::Observe(const JointSample& s, const Eigen::VectorXd& residual) noexcept {
  if (!options_.threaded) {
    std::lock_guard<std::mutex> lock(diagnosis_mutex_);
    if (Fill(s, residual, &scratch_)) AddToDiagnosis(scratch_);
    return;
  }
  std::lock_guard<std::mutex> lock(ring_mutex_);
  if (size_ == ring_.size()) {
    dropped_.fetch_add(1, std::memory_order_relaxed);
    return;
  }
  if (Fill(s, residual, &ring_[(head_ + size_) % ring_.size()])) ++size_;
}

void StreamDiagnosis::Drain() {
  std::lock_guard<std::mutex> draining(drain_mutex_);  // the worker and EvaluateNow share scratch_
  for (;;) {
    {
      std::lock_guard<std::mutex> lock(ring_mutex_);
      if (size_ == 0) return;
      std::swap(scratch_, ring_[head_]);  // sizes are equal: no allocation
      if (reset_pending_) {
        scratch_.reset = true;  // a reset the full ring could not hold, before this sample
        reset_pending_ = false;
      }
      head_ = (head_ + 1) % ring_.size();
      --size_;
    }
    std::lock_guard<std::mutex> lock(diagnosis_mutex_);
    if (scratch_.reset) {
      diagnosis_.Reset();
      if (!scratch_.sample) continue;  // a reset marker only
    }
    AddToDiagnosis(scratch_);
  }
}

StreamJudgement StreamDiagnosis::Judge(const std::vector<OnlineBodyState>& bodies, const Eigen::VectorXd& x) const {
  StreamJudgement j;
  j.diagnosis = diagnosis_.Evaluate(bodies);
  if (excitation_ && x.size() == diagnosis_.model().num_parameters()) j.excitation = excitation_->Evaluate(x);
  return j;
}

void StreamDiagnosis::Work() {
  while (!stop_) {
    std::optional<std::vector<OnlineBodyState>> request;
    Eigen::VectorXd x;
    {
      std::unique_lock<std::mutex> lock(result_mutex_);
      // Woken early for a request; otherwise every 5 ms (the producer never signals per sample).
      wake_.wait_for(lock, std::chrono::milliseconds(5), [this] { return stop_ || request_; });
      request.swap(request_);
      x.swap(request_x_);
    }
    Drain();
    if (request) {
      StreamJudgement r;
      {
        std::lock_guard<std::mutex> lock(diagnosis_mutex_);
        r = Judge(*request, x);
      }
      std::lock_guard<std::mutex> lock(result_mutex_);
      latest_ = std::move(r);
    }
  }
}

void StreamDiagnosis::Reset() {
  if (!options_.threaded) {
    std::lock_guard<std::mutex> lock(diagnosis_mutex_);
    diagnosis_.Reset();
    return;
  }
  // In the ring, in order: the samples before it are judged with the old system, those after with
  // the new. A full ring: the reset is applied before the next sample drained.
  std::lock_guard<std::mutex> lock(ring_mutex_);
  if (size_ == ring_.size()) {
    reset_pending_ = true;
    return;
  }
  Entry& marker = ring_[(head_ + size_) % ring_.size()];
  marker.reset = true;
  marker.sample = false;
  ++size_;
}

void StreamDiagnosis::RequestEvaluation(std::vector<OnlineBodyState> bodies, Eigen::VectorXd x) {
  if (!options_.threaded) {
    StreamJudgement r = EvaluateNow(bodies, x);
    std::lock_guard<std::mutex> lock(result_mutex_);
    latest_ = std::move(r);
    return;
  }
  {
    std::lock_guard<std::mutex> lock(result_mutex_);
    request_ = std::move(bodies);
    request_x_ = std::move(x);
  }
  wake_.notify_one();
}

std::optional<StreamJudgement> StreamDiagnosis::Latest() const {
  std::lock_guard<std::mutex> lock(result_mutex_);
  return latest_;
}

StreamJudgement StreamDiagnosis::EvaluateNow(const std::vector<OnlineBodyState>& bodies, const Eigen::VectorXd& x) {
  if (options_.threaded) Drain();
  std::lock_guard<std::mutex> lock(diagnosis_mutex_);
  return Judge(bodies, x);
}

}  // namespace inertial
