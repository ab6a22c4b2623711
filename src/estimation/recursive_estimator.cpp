#include "inertial/estimation/recursive_estimator.hpp"

#include <cmath>

namespace inertial {

UpdateStatus RecursiveEstimator::Update(double t, const Eigen::MatrixXd& A, const Eigen::VectorXd& y) {
  UpdateStatus status = UpdateStatus::kAccepted;
  if (A.rows() != num_measurements_ || A.cols() != num_features_ || y.size() != num_measurements_) {
    status = UpdateStatus::kWrongSize;
  } else if (!std::isfinite(t) || !A.allFinite() || !y.allFinite()) {
    status = UpdateStatus::kNonFinite;
  } else if (has_time_ && !(t > last_time_)) {
    status = UpdateStatus::kOutOfOrder;
  } else {
    status = Apply(A, y);
  }
  counters_.Add(status);
  if (status == UpdateStatus::kAccepted || status == UpdateStatus::kOutlier) {
    // An outlier is still a valid sample in time: later samples must come after it.
    has_time_ = true;
    last_time_ = t;
  }
  return status;
}

EstimatorState RecursiveEstimator::State() const {
  EstimatorState s;
  s.kind = std::string(kind());
  s.x = parameters();
  s.P = Covariance();
  s.has_time = has_time_;
  s.last_time = last_time_;
  s.counters = counters_;
  return s;
}

bool RecursiveEstimator::Restore(const EstimatorState& state, std::string* why) {
  if (state.kind != kind()) {
    if (why != nullptr) *why = "the state is of a '" + state.kind + "' estimator, this one is '" + std::string(kind()) + "'";
    return false;
  }
  if (state.x.size() != num_parameters()) {
    if (why != nullptr) {
      *why = "the state has " + std::to_string(state.x.size()) + " parameters, the model " +
             std::to_string(num_parameters()) + " (a different model or effects?)";
    }
    return false;
  }
  if (!state.x.allFinite() || (state.has_time && !std::isfinite(state.last_time))) {
    if (why != nullptr) *why = "the state holds non-finite numbers";
    return false;
  }
  if (!SetParameters(state.x, state.P, why)) return false;
  has_time_ = state.has_time;
  last_time_ = state.last_time;
  counters_ = state.counters;
  return true;
}

}  // namespace inertial
