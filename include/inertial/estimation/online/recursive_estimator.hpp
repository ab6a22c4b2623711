/// @file recursive_estimator.hpp
/// The interface of the online estimators (recursive Gauss-Newton, gradient law, linear recursive
/// least squares): one sample at a time of a model linear in coefficients w(x),
///
///   y = A w(x) + noise,     A: m x F features of the sample (joint-torque regressor and effect
///                           features, or one body's Newton-Euler regressor), y: m measurements.
///
/// Update() validates the sample (sizes, finiteness, strictly increasing time), then hands it to
/// the estimator. It never allocates and never throws: a sample that cannot be used is rejected
/// with a status and counted, and the estimate stays exactly as it was. All memory is sized at
/// construction. The state (x, covariance, time, counters) can be saved and restored, so a
/// restarted process continues where it stopped.
#pragma once

#include <cmath>
#include <cstdint>
#include <string>

#include <Eigen/Core>

#include "inertial/signal/update_status.hpp"

namespace inertial {

/// Everything an estimator needs to continue: parameters, covariance (empty for the gradient law),
/// time of the last accepted sample and the counters.
struct EstimatorState {
  std::string kind;         ///< "gauss_newton", "gradient" or "linear_rls"
  Eigen::VectorXd x;
  Eigen::MatrixXd P;        ///< full symmetric, or empty
  bool has_time = false;
  double last_time = 0.0;
  UpdateCounters counters;
  /// OnlineFit (online_fit.hpp): its sufficient statistics [S s; s^T c] ((F+1) x (F+1), normalized),
  /// their effective sample count and whether a solve has run; empty for the other estimators.
  Eigen::MatrixXd statistics;
  double statistics_samples = 0.0;
  bool solved = false;
  /// The gradient law's memory of its last direction (gradient_estimator.hpp); empty for the others.
  Eigen::VectorXd directions;
};

/// Largest |time| [s] a restored state may hold: 1e10 s is year 2286 as Unix time (time stamps are
/// seconds since some epoch; nothing a robot logs lies beyond).
inline constexpr double kMaxStateTime = 1e10;
/// Largest |coefficient| of w(x) a restored state may give, in SI units (kg, kg m, kg m^2, N m ...):
/// six orders of magnitude above the heaviest robots' links (1e3 kg, 1e3 kg m^2); beyond it the
/// torques A w lose every digit of the measured ones.
inline constexpr double kMaxStateCoefficient = 1e9;

class RecursiveEstimator {
 public:
  virtual ~RecursiveEstimator() = default;

  /// One sample at time t [s]. A: num_measurements() x num_features(), y: num_measurements().
  UpdateStatus Update(double t, const Eigen::MatrixXd& A, const Eigen::VectorXd& y);

  virtual std::string_view kind() const = 0;
  int num_features() const { return num_features_; }
  int num_measurements() const { return num_measurements_; }
  int num_parameters() const { return static_cast<int>(parameters().size()); }
  /// x (log-Cholesky theta and effect parameters, or pi itself for linear RLS).
  virtual const Eigen::VectorXd& parameters() const = 0;
  /// w(x) into w (num_features()). Allocation-free.
  virtual void Coefficients(Eigen::Ref<Eigen::VectorXd> w) const = 0;
  /// Covariance of x (allocates); empty for estimators that keep none.
  virtual Eigen::MatrixXd Covariance() const = 0;
  /// How many changes of the system the estimator's change detector has taken (a run of more than
  /// KalmanOptions::max_consecutive_outliers outliers: the covariance reset, kalman_update.hpp);
  /// 0 for an estimator without one. Allocation-free.
  virtual std::uint64_t changes_detected() const { return 0; }

  const UpdateCounters& counters() const { return counters_; }
  /// Counts a sample that an adapter (e.g. OnlineJointEstimator) rejected or buffered before Update().
  void CountSample(UpdateStatus status) { counters_.Add(status); }
  bool has_time() const { return has_time_; }
  double last_time() const { return last_time_; }

  EstimatorState State() const;
  /// Restores a State() of an estimator of the same kind and sizes. Returns false (and *why says
  /// what is wrong) without changing anything when it does not match or is not a usable state:
  /// non-finite numbers, |last_time| > kMaxStateTime, a covariance that is not symmetric positive
  /// definite, or coefficients w(x) beyond kMaxStateCoefficient.
  bool Restore(const EstimatorState& state, std::string* why);

 protected:
  RecursiveEstimator(int num_features, int num_measurements)
      : num_features_(num_features), num_measurements_(num_measurements) {}
  /// What Update() does around the estimator's own update, for entry points with other types
  /// (the fixed-size body estimators): refuses a sample of wrong sizes, non-finite numbers or a
  /// time not after the last one, else calls apply(); counts the outcome and keeps the time.
  template <class ApplyFn>
  UpdateStatus Admit(double t, bool sizes_ok, bool finite, ApplyFn&& apply) {
    UpdateStatus status = UpdateStatus::kAccepted;
    if (!sizes_ok) {
      status = UpdateStatus::kWrongSize;
    } else if (!std::isfinite(t) || !finite) {
      status = UpdateStatus::kNonFinite;
    } else if (has_time_ && !(t > last_time_)) {
      status = UpdateStatus::kOutOfOrder;
    } else {
      applying_time_ = t;
      status = apply();
    }
    counters_.Add(status);
    if (status == UpdateStatus::kAccepted || status == UpdateStatus::kOutlier || status == UpdateStatus::kBuffered) {
      // An outlier or a held sample is still a valid sample in time: later ones must come after it.
      has_time_ = true;
      last_time_ = t;
    }
    return status;
  }
  /// The estimator's own update of a validated sample; must leave the estimate untouched unless it
  /// returns kAccepted.
  virtual UpdateStatus Apply(const Eigen::MatrixXd& A, const Eigen::VectorXd& y) = 0;
  virtual bool SetParameters(const Eigen::VectorXd& x, const Eigen::MatrixXd& P, std::string* why) = 0;
  /// The covariance State() saves (Covariance() unless the estimator keeps another state).
  virtual Eigen::MatrixXd StateCovariance() const { return Covariance(); }
  /// Adds what else the estimator keeps to a State() / takes it from a state being restored (after
  /// SetParameters succeeded; returning false undoes nothing, so check first).
  virtual void SaveExtra(EstimatorState*) const {}
  virtual bool CheckExtra(const EstimatorState&, std::string*) const { return true; }
  virtual void RestoreExtra(const EstimatorState&) {}
  /// A sample counted kBuffered is resolved: moved from buffered to `to` (kAccepted or a rejection).
  void Resolve(UpdateStatus to) {
    if (counters_.count[static_cast<int>(UpdateStatus::kBuffered)] > 0) --counters_.count[static_cast<int>(UpdateStatus::kBuffered)];
    counters_.Add(to);
  }
  /// The time of the sample being applied (valid inside Apply()).
  double applying_time() const { return applying_time_; }

 private:
  int num_features_, num_measurements_;
  UpdateCounters counters_;
  bool has_time_ = false;
  double last_time_ = 0.0;
  double applying_time_ = 0.0;
};

}  // namespace inertial
