#include "inertial/estimation/kalman_update.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include "inertial/inertia/assert.hpp"

namespace inertial {

KalmanUpdate::KalmanUpdate(int n, int m, const Eigen::VectorXd& initial_std, const KalmanOptions& options)
    : options_(options), llt_(m > 0 ? m : 1) {
  if (n < 1 || m < 1) throw std::invalid_argument("Kalman update: needs at least one parameter and one measurement");
  if (initial_std.size() != n || !initial_std.allFinite() || !(initial_std.array() > 0).all()) {
    throw std::invalid_argument("Kalman update: initial standard deviations must be " + std::to_string(n) +
                                " positive finite numbers");
  }
  const KalmanOptions& o = options;
  if (!(o.measurement_sigma > 0 && std::isfinite(o.measurement_sigma))) throw std::invalid_argument("Kalman update: measurement sigma must be positive");
  if (!(o.forgetting > 0 && o.forgetting <= 1)) throw std::invalid_argument("Kalman update: forgetting must be in (0, 1]");
  if (!(o.process_noise >= 0 && std::isfinite(o.process_noise))) throw std::invalid_argument("Kalman update: process noise must be >= 0");
  if (!(o.max_variance_factor > 0)) throw std::invalid_argument("Kalman update: max variance factor must be positive");
  if (!(o.huber > 0) || !(o.gate > 0)) throw std::invalid_argument("Kalman update: Huber threshold and gate must be positive");
  if (o.max_consecutive_outliers < 0) throw std::invalid_argument("Kalman update: bad outlier options");
  if (!(o.max_step > 0)) throw std::invalid_argument("Kalman update: max step must be positive");
  P_ = initial_std.array().square().matrix().asDiagonal();
  cap_ = o.max_variance_factor * initial_std.array().square();
  blocked_ = n >= kBlockedThreshold;
  forget_.resize(n);
  PHt_.resize(n, m);
  W_.resize(n, m);
  S_.resize(m, m);
  z_.resize(m);
  dx_ = Eigen::VectorXd::Zero(n);
}

UpdateStatus KalmanUpdate::Step(const Eigen::MatrixXd& H, const Eigen::VectorXd& r) {
  INERTIAL_ASSERT(H.rows() == S_.rows() && H.cols() == P_.rows() && r.size() == S_.rows());
  H_ = &H;
  r_ = &r;
  const int m = static_cast<int>(S_.rows());
  // Prediction: selective forgetting (P <- D P D, D_ii = lambda^-1/2 below the cap, 1 above) and
  // process noise below the cap.
  if (options_.forgetting < 1.0 || options_.process_noise > 0.0) {
    const double f = 1.0 / std::sqrt(options_.forgetting);
    for (int i = 0; i < P_.rows(); ++i) forget_[i] = P_(i, i) < cap_[i] ? f : 1.0;
    if (options_.forgetting < 1.0) {
      for (int j = 0; j < P_.cols(); ++j) P_.col(j).array() *= forget_[j] * forget_.array();
    }
    if (options_.process_noise > 0.0) {
      for (int i = 0; i < P_.rows(); ++i) {
        if (P_(i, i) < cap_[i]) P_(i, i) += options_.process_noise;
      }
    }
  }
  Predict(H);
  if (!Factor(1.0)) return UpdateStatus::kNumerical;
  normalized_innovation_ = std::sqrt(z_.squaredNorm() / m);
  if (normalized_innovation_ > options_.gate && !tracking_change_) {
    if (++consecutive_outliers_ <= options_.max_consecutive_outliers) return UpdateStatus::kOutlier;
    // A persistent change, not an outlier (a payload picked up): inflate P once and take every
    // sample until the innovations are back inside the gate.
    tracking_change_ = true;
    ++changes_;
    // Everything may have changed: back to the initial uncertainty about the current estimate.
    P_ = cap_.asDiagonal();
    P_ /= options_.max_variance_factor;
    Predict(H);
    if (!Factor(1.0)) return UpdateStatus::kNumerical;
  } else if (normalized_innovation_ <= options_.gate) {
    consecutive_outliers_ = 0;
    tracking_change_ = false;
  }
  const double e = std::sqrt(z_.squaredNorm() / m);
  if (e > options_.huber && !Factor(options_.huber / e)) return UpdateStatus::kNumerical;
  // W = P H^T L^-T: W L^T = P H^T, solved column by column (m is small).
  const Eigen::MatrixXd& L = llt_.matrixLLT();  // lower triangle holds L
  for (int j = 0; j < W_.cols(); ++j) {
    W_.col(j) = PHt_.col(j);
    for (int k = 0; k < j; ++k) W_.col(j) -= L(j, k) * W_.col(k);
    W_.col(j) /= L(j, j);
  }
  dx_.noalias() = W_ * z_;
  if (!dx_.allFinite() || !W_.allFinite()) return UpdateStatus::kNumerical;
  const double largest = dx_.lpNorm<Eigen::Infinity>();
  step_scale_ = largest > options_.max_step ? options_.max_step / largest : 1.0;
  dx_ *= step_scale_;
  return UpdateStatus::kAccepted;
}

void KalmanUpdate::Predict(const Eigen::MatrixXd& H) {
  if (blocked_) {
    // Large P: a symmetric blocked product reading the lower triangle (Eigen's SYMM).
    PHt_.noalias() = P_.selfadjointView<Eigen::Lower>() * H.transpose();
  } else {
    // Small P: m matrix-vector products (the blocked kernels' packing costs more than it saves).
    for (int i = 0; i < PHt_.cols(); ++i) PHt_.col(i).noalias() = P_ * H.row(i).transpose();
  }
}

bool KalmanUpdate::Factor(double weight) {
  S_.noalias() = H_->lazyProduct(PHt_);
  S_.diagonal().array() += options_.measurement_sigma * options_.measurement_sigma / weight;
  llt_.compute(S_);
  if (llt_.info() != Eigen::Success) return false;
  z_ = *r_;
  llt_.matrixL().solveInPlace(z_);
  return z_.allFinite();
}

void KalmanUpdate::Commit(double fraction) {
  // A step cut to a fraction of the Kalman step used only that fraction of the sample's
  // information: the covariance shrinks by as much (P - f W W^T stays positive definite for f <= 1).
  // m rank-one updates, column by column (vectorized axpys), P kept symmetric in full.
  const double f = fraction * step_scale_;
  if (blocked_) {
    P_.selfadjointView<Eigen::Lower>().rankUpdate(W_, -f);  // lower triangle only (SYRK)
  } else {
    for (int j = 0; j < P_.cols(); ++j) {
      for (int k = 0; k < W_.cols(); ++k) P_.col(j).noalias() -= (f * W_(j, k)) * W_.col(k);
    }
  }
}

Eigen::MatrixXd KalmanUpdate::Covariance() const {
  if (blocked_) return P_.selfadjointView<Eigen::Lower>();
  return P_;  // kept in full; symmetric up to rounding
}

bool KalmanUpdate::SetCovariance(const Eigen::MatrixXd& P) {
  if (P.rows() != P_.rows() || P.cols() != P_.cols() || !P.allFinite()) return false;
  P_ = P;  // exactly, so that a restored estimator continues bit for bit
  return true;
}

}  // namespace inertial
