/// @file kalman_update.hpp
/// The measurement update shared by the recursive estimators, in covariance (Kalman) form, for a
/// model linearized as y ~ y_hat + H dx with m measurements of standard deviation sigma:
///
///   P <- D P D + q 1                          (forgetting and process noise; D_ii = lambda^-1/2 for
///                                              the parameters whose variance is below its cap)
///   S = H P H^T + (sigma^2 / omega) 1,  S = L L^T
///   z = L^-1 r,  d^2 = |z|^2                  (r = y - y_hat; d^2: the Mahalanobis distance)
///   W = P H^T L^-T,  dx = W z,  P <- P - W W^T
///
/// Forgetting is selective: a parameter the data do not excite stops growing at its cap (its
/// initial variance times max_variance_factor), so it cannot wind up and random-walk (the others
/// keep forgetting). Cost O(n^2 m) (m matrix-vector products with P and m rank-one updates; never
/// n^3), written as vectorized column operations rather than blocked matrix products, which
/// cost more than they save at these sizes.
/// Robustness: samples with sqrt(d^2 / m) > gate are rejected as outliers, unless more than
/// max_consecutive_outliers in a row arrive (then the world has changed, e.g. a payload was picked
/// up: P is reset to its initial value around the current estimate, and samples are taken,
/// Huber-weighted, until the innovations are back inside the gate); Huber weighting omega = min(1, huber / sqrt(d^2/m))
/// damps the rest; the step is scaled to |dx|_inf <= max_step. Allocation-free after construction,
/// no exceptions on Step/Commit.
#pragma once

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <cstdint>
#include <limits>

#include "inertial/estimation/update_status.hpp"

namespace inertial {

struct KalmanOptions {
  double measurement_sigma = 1.0;  ///< standard deviation of each measurement (N m, N, ...)
  double forgetting = 1.0;         ///< lambda in (0, 1]: P /= lambda per sample (1: none)
  double process_noise = 0.0;      ///< variance added to every diagonal entry of P per sample
  double max_variance_factor = 1.0;  ///< cap of P_ii for forgetting and process noise, times its initial value
  double huber = 3.0;              ///< normalized innovation (sigmas) where down-weighting starts
  double gate = 30.0;              ///< normalized innovation (sigmas) beyond which a sample is an outlier
  int max_consecutive_outliers = 50;  ///< more in a row: a change; P back to its initial value
  double max_step = 0.5;              ///< bound on |dx|_inf per sample
};

class KalmanUpdate {
 public:
  /// @throws std::invalid_argument for sizes < 1, non-positive or non-finite initial_std, or
  /// options out of range (sigma <= 0, forgetting outside (0, 1], ...).
  KalmanUpdate(int num_parameters, int num_measurements, const Eigen::VectorXd& initial_std,
               const KalmanOptions& options);

  /// Computes dx from H (m x n) and r (m) and leaves P predicted; kAccepted, kOutlier or
  /// kNumerical. Preconditions (debug-asserted): sizes. The caller applies dx and then Commit()s.
  UpdateStatus Step(const Eigen::MatrixXd& H, const Eigen::VectorXd& r);
  /// P <- P - f W W^T for the last accepted Step, f = fraction times the step-limit scale (1 for a
  /// full Kalman step): a shortened step takes only part of the sample's information.
  void Commit(double fraction = 1.0);
  const Eigen::VectorXd& step() const { return dx_; }
  /// sqrt(d^2 / m) of the last Step (before any Huber weighting), in sigmas.
  double normalized_innovation() const { return normalized_innovation_; }
  /// How often a run of more than max_consecutive_outliers was taken as a change of the system.
  std::uint64_t changes_detected() const { return changes_; }

  /// The covariance of x (full symmetric; allocates).
  Eigen::MatrixXd Covariance() const;
  /// Parameters from which P is kept as its lower triangle and updated by symmetric blocked
  /// products; below, P is kept in full and updated by vectorized column operations.
  static constexpr int kBlockedThreshold = 32;
  /// Replaces P (symmetric, n x n); false if the size is wrong or it is not finite.
  bool SetCovariance(const Eigen::MatrixXd& P);
  const KalmanOptions& options() const { return options_; }
  int num_parameters() const { return static_cast<int>(P_.rows()); }
  int num_measurements() const { return static_cast<int>(S_.rows()); }

 private:
  void Predict(const Eigen::MatrixXd& H);  // PHt_ = P H^T
  bool Factor(double weight);  // S, its Cholesky factor and z for the current PHt_, r_
  KalmanOptions options_;
  Eigen::MatrixXd P_, PHt_, S_, W_;
  Eigen::VectorXd cap_, forget_;
  Eigen::LLT<Eigen::MatrixXd> llt_;
  Eigen::VectorXd z_, dx_;
  const Eigen::MatrixXd* H_ = nullptr;
  const Eigen::VectorXd* r_ = nullptr;
  int consecutive_outliers_ = 0;
  bool tracking_change_ = false;
  std::uint64_t changes_ = 0;
  double normalized_innovation_ = 0.0;
  double step_scale_ = 1.0;
  bool blocked_ = false;
};

}  // namespace inertial
