/// @file kalman_update.hpp
/// The measurement update shared by the recursive estimators, in covariance (Kalman) form, for a
/// model linearized as y ~ y_hat + H dx with m measurements of standard deviation sigma:
///
///   P <- D P D + Q                            (forgetting and process noise; D_ii = lambda^-1/2 and
///                                              Q_ii = q for the parameters whose variance is below its cap)
///   S = H P H^T + (sigma^2 / omega) 1,  S = L L^T
///   z = L^-1 r,  d^2 = |z|^2                  (r = y - y_hat; d^2: the Mahalanobis distance)
///   W = P H^T L^-T,  dx = W z,  P <- P - W W^T
///
/// Forgetting is selective: a parameter the data do not excite stops growing at its cap (its
/// initial variance times max_variance_factor), so it cannot wind up and random-walk (the others
/// keep forgetting).
/// Cost: P is symmetric and only its lower triangle is kept and updated. A robot's regressor is
/// block-triangular (a joint's torque depends only on the bodies it carries and its own effects),
/// so each row of H is nonzero only over a span [first, end) of the parameters; P H^T is formed
/// from the lower triangle over those spans alone (n (end - first) per measurement, in groups of
/// kSpanBlock measurements so that each element of P read serves all of them), S over the spans, and
/// the rank-m downdate of the lower triangle costs n^2 m / 2, fused with the next prediction into one
/// pass over P (symmetric_rank_update.hpp). Dense H costs 1.5 n^2 m multiply-adds,
/// a serial chain's about 1.05 n^2 m (against 2 n^2 m for full storage and dense products);
/// never n^3.
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

#include "inertial/signal/update_status.hpp"

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

/// N parameters, M measurements: Eigen::Dynamic for both (any robot; the span products above), or
/// compile-time sizes (one body: BodyKalmanUpdate, fixed-size dense products with P kept in full,
/// its rows padded to whole SIMD packets, S factored by an unrolled loop, no loops over run-time sizes).
template <int N, int M>
class BasicKalmanUpdate {
 public:
  using MatrixH = Eigen::Matrix<double, M, N>;
  using VectorM = Eigen::Matrix<double, M, 1>;
  using VectorN = Eigen::Matrix<double, N, 1>;
  static constexpr bool kDynamic = N == Eigen::Dynamic;
  static_assert((N == Eigen::Dynamic) == (M == Eigen::Dynamic), "both sizes dynamic or both fixed");

  /// @throws std::invalid_argument for sizes < 1 (or not N, M), non-positive or non-finite
  /// initial_std, or options out of range (sigma <= 0, forgetting outside (0, 1], ...).
  BasicKalmanUpdate(int num_parameters, int num_measurements, const Eigen::VectorXd& initial_std,
                    const KalmanOptions& options);

  /// Computes dx from H (m x n) and r (m) and leaves P predicted; kAccepted, kOutlier or
  /// kNumerical. Preconditions (debug-asserted): sizes. The caller applies dx and then Commit()s.
  UpdateStatus Step(const MatrixH& H, const VectorM& r);
  /// P <- P - f W W^T for the last accepted Step, f = fraction times the step-limit scale (1 for a
  /// full Kalman step): a shortened step takes only part of the sample's information.
  void Commit(double fraction = 1.0);
  const VectorN& step() const { return dx_; }
  /// sqrt(d^2 / m) of the last Step (before any Huber weighting), in sigmas.
  double normalized_innovation() const { return normalized_innovation_; }
  /// How often a run of more than max_consecutive_outliers was taken as a change of the system.
  std::uint64_t changes_detected() const { return changes_; }

  /// The covariance of x (full symmetric; allocates): the last posterior, with the prediction of
  /// any later sample that was not committed (refused as an outlier, say) applied.
  Eigen::MatrixXd Covariance() const;
  /// Replaces P (symmetric, n x n); false if the size is wrong or it is not finite.
  bool SetCovariance(const Eigen::MatrixXd& P);
  const KalmanOptions& options() const { return options_; }
  int num_parameters() const { return n_; }
  int num_measurements() const { return m_; }

 private:
  void Transpose(const MatrixH& H);  // Ht_ = H^T and the spans first_, end_
  void Predict();                    // PHt_ = P H^T (from Ht_)
  // S, its Cholesky factor and z for the current PHt_, r_ (fixed sizes: S factored by an unrolled
  // loop, and W = P H^T L^-T formed here too)
  bool Factor(const MatrixH& H, double weight);
  void ChoosePrediction();           // forget_ and noise_ from P's diagonal (the variance caps)
  template <class Matrix>
  void ApplyPrediction(Matrix& P) const;  // P <- D P D + Q alone (for a step that was not committed)
  void ResetCovariance();            // P back to its initial value, no prediction pending
  KalmanOptions options_;
  int n_ = 0, m_ = 0;
  // Dynamic sizes: the lower triangle (the strictly upper part is not kept up to date); P_, Ht_
  // and PHt_ padded with zeros to whole blocks of the span product. Fixed sizes: P in full, its
  // rows (and those of H^T) padded with zeros to whole SIMD packets of 4 doubles (10 -> 12), so
  // that every column is whole packets and no product has a scalar tail.
  static constexpr int kRows = kDynamic ? Eigen::Dynamic : (N + 3) / 4 * 4;
  using VectorS = Eigen::Matrix<double, kRows, 1>;
  Eigen::Matrix<double, kRows, kRows> P_;
  Eigen::Matrix<double, kRows, M> Ht_, HtD_, PHt_, W_;  // H^T, D H^T, P_predicted H^T, P_predicted H^T L^-T
  Eigen::Matrix<double, M, M> S_;
  Eigen::Matrix<int, M, 1> first_, end_;  // per measurement: H's nonzero columns are [first, end)
  // The prediction is never applied to P on its own: P stays the last posterior, D and Q enter
  // P H^T as O(n m) scalings, and Commit() forms D P D + Q - f W W^T in one pass
  // (symmetric_rank_update.hpp). pending_: a prediction chosen by Step() and not yet committed.
  VectorS cap_, forget_, noise_;  // D's diagonal (padding: 1), Q's diagonal (padding: 0)
  bool scaled_ = false, pending_ = false;
  Eigen::LLT<Eigen::Matrix<double, M, M>> llt_;
  VectorM z_;
  VectorN dx_;
  const VectorM* r_ = nullptr;
  int consecutive_outliers_ = 0;
  bool tracking_change_ = false;
  std::uint64_t changes_ = 0;
  double normalized_innovation_ = 0.0;
  double step_scale_ = 1.0;
};

/// Any number of parameters and measurements.
using KalmanUpdate = BasicKalmanUpdate<Eigen::Dynamic, Eigen::Dynamic>;
/// One body's 10 parameters and the 6 components of its wrench.
using BodyKalmanUpdate = BasicKalmanUpdate<10, 6>;
extern template class BasicKalmanUpdate<Eigen::Dynamic, Eigen::Dynamic>;
extern template class BasicKalmanUpdate<10, 6>;

}  // namespace inertial
