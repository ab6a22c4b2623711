#include "inertial/runtime/stream_diagnosis.hpp"

#include <chrono>
#include <stdexcept>

namespace inertial {

std::vector<OnlineBodyState> BodyStatesOf(const OnlineJointEstimator& estimator) {
  return OnlineBodyStates(estimator.model(), estimator.estimator().parameters(), estimator.estimator().Covariance(),
                          estimator.kind() == EstimatorKind::kLinearRls);
}

StreamDiagnosis::StreamDiagnosis(const RobotDynamics& model, const StreamDiagnosisOptions& options)
    : diagnosis_(model, options.diagnosis), options_(options) {
  if (options.capacity < 1) throw std::invalid_argument("stream diagnosis: the ring needs a capacity of at least 1");
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

void StreamDiagnosis::Observe(const JointSample& s, const Eigen::VectorXd& residual) noexcept {
  if (!options_.threaded) {
    std::lock_guard<std::mutex> lock(diagnosis_mutex_);
    diagnosis_.Add(s.t, s.q, s.qd, s.qdd, s.tau, residual);
    return;
  }
  std::lock_guard<std::mutex> lock(ring_mutex_);
  if (size_ == ring_.size()) {
    dropped_.fetch_add(1, std::memory_order_relaxed);
    return;
  }
  Entry& e = ring_[(head_ + size_) % ring_.size()];
  if (s.q.size() != e.q.size() || s.qd.size() != e.q.size() || s.qdd.size() != e.q.size() ||
      s.tau.size() != e.q.size() || residual.size() != e.q.size()) {
    return;  // not a sample of this model: OnlineDiagnosis::Add would ignore it too
  }
  e.t = s.t;
  e.q = s.q;
  e.qd = s.qd;
  e.qdd = s.qdd;
  e.tau = s.tau;
  e.residual = residual;
  ++size_;
}

void StreamDiagnosis::Drain() {
  std::lock_guard<std::mutex> draining(drain_mutex_);  // the worker and EvaluateNow share scratch_
  for (;;) {
    {
      std::lock_guard<std::mutex> lock(ring_mutex_);
      if (size_ == 0) return;
      std::swap(scratch_, ring_[head_]);  // sizes are equal: no allocation
      head_ = (head_ + 1) % ring_.size();
      --size_;
    }
    std::lock_guard<std::mutex> lock(diagnosis_mutex_);
    diagnosis_.Add(scratch_.t, scratch_.q, scratch_.qd, scratch_.qdd, scratch_.tau, scratch_.residual);
  }
}

void StreamDiagnosis::Work() {
  while (!stop_) {
    bool reset = false;
    std::optional<std::vector<OnlineBodyState>> request;
    {
      std::unique_lock<std::mutex> lock(result_mutex_);
      // Woken early for a request; otherwise every 5 ms (the producer never signals per sample).
      wake_.wait_for(lock, std::chrono::milliseconds(5), [this] { return stop_ || request_ || reset_requested_; });
      reset = reset_requested_;
      reset_requested_ = false;
      request.swap(request_);
    }
    Drain();
    if (reset) {
      std::lock_guard<std::mutex> lock(diagnosis_mutex_);
      diagnosis_.Reset();
    }
    if (request) {
      OnlineDiagnosisResult r;
      {
        std::lock_guard<std::mutex> lock(diagnosis_mutex_);
        r = diagnosis_.Evaluate(*request);
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
  {
    std::lock_guard<std::mutex> lock(result_mutex_);
    reset_requested_ = true;
  }
  wake_.notify_one();
}

void StreamDiagnosis::RequestEvaluation(std::vector<OnlineBodyState> bodies) {
  if (!options_.threaded) {
    OnlineDiagnosisResult r = EvaluateNow(bodies);
    std::lock_guard<std::mutex> lock(result_mutex_);
    latest_ = std::move(r);
    return;
  }
  {
    std::lock_guard<std::mutex> lock(result_mutex_);
    request_ = std::move(bodies);
  }
  wake_.notify_one();
}

std::optional<OnlineDiagnosisResult> StreamDiagnosis::Latest() const {
  std::lock_guard<std::mutex> lock(result_mutex_);
  return latest_;
}

OnlineDiagnosisResult StreamDiagnosis::EvaluateNow(const std::vector<OnlineBodyState>& bodies) {
  if (options_.threaded) Drain();
  std::lock_guard<std::mutex> lock(diagnosis_mutex_);
  return diagnosis_.Evaluate(bodies);
}

}  // namespace inertial
