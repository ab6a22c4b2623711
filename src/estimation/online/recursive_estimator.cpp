#include "inertial/estimation/online/recursive_estimator.hpp"

#include <Eigen/Cholesky>
#include <cmath>
#include <string>

namespace inertial {

UpdateStatus RecursiveEstimator::Update(double t, const Eigen::MatrixXd& A, const Eigen::VectorXd& y) {
  const bool sizes_ok = A.rows() == num_measurements_ && A.cols() == num_features_ && y.size() == num_measurements_;
  return Admit(t, sizes_ok, sizes_ok && A.allFinite() && y.allFinite(), [&] { return Apply(A, y); });
}

EstimatorState RecursiveEstimator::State() const {
  EstimatorState s;
  s.kind = std::string(kind());
  s.x = parameters();
  s.P = StateCovariance();
  s.has_time = has_time_;
  s.last_time = last_time_;
  s.counters = counters_;
  SaveExtra(&s);  // last: it may move held samples' counts (online_fit.hpp)
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
  // A restored state is checked as strictly as a sample: one that would make every later sample
  // fail (a time far in the future, a covariance no update can use, a body beyond any physical
  // scale) would wedge the estimator and be written back at every checkpoint.
  if (state.has_time && !(std::abs(state.last_time) <= kMaxStateTime)) {
    if (why != nullptr) {
      *why = "its last sample time " + std::to_string(state.last_time) + " s is beyond " + std::to_string(kMaxStateTime) +
             " s (every later sample would be out of order)";
    }
    return false;
  }
  if (state.P.size() > 0) {
    if (state.P.rows() != state.P.cols() || !state.P.allFinite()) {
      if (why != nullptr) *why = "its covariance is not a square matrix of finite numbers";
      return false;
    }
    const double scale = state.P.cwiseAbs().maxCoeff();
    if (!((state.P - state.P.transpose()).cwiseAbs().maxCoeff() <= 1e-9 * scale)) {
      if (why != nullptr) *why = "its covariance is not symmetric";
      return false;
    }
    if (Eigen::LLT<Eigen::MatrixXd>(state.P).info() != Eigen::Success || !(scale > 0)) {
      if (why != nullptr) *why = "its covariance is not positive definite";
      return false;
    }
  }
  if (!CheckExtra(state, why)) return false;
  const EstimatorState before = State();
  if (!SetParameters(state.x, state.P, why)) return false;
  Eigen::VectorXd w(num_features_);
  Coefficients(w);
  if (!w.allFinite() || !(w.cwiseAbs().maxCoeff() <= kMaxStateCoefficient)) {
    std::string ignored;
    SetParameters(before.x, before.P, &ignored);  // back to what it was: nothing changes
    if (why != nullptr) {
      *why = "its parameters give coefficients (masses, moments, friction) beyond " + std::to_string(kMaxStateCoefficient) +
             " in SI units or not finite: outside the parameterization's useful range";
    }
    return false;
  }
  RestoreExtra(state);
  has_time_ = state.has_time;
  last_time_ = state.last_time;
  counters_ = state.counters;
  return true;
}

}  // namespace inertial
