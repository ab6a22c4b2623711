#include "inertial/estimation/online/kalman_update.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "inertial/estimation/online/symmetric_rank_update.hpp"
#include "inertial/estimation/online/symmetric_span_product.hpp"
#include "inertial/inertia/assert.hpp"

namespace inertial {

namespace {
int RoundUpToBlock(int k) { return (k + kSpanBlock - 1) / kSpanBlock * kSpanBlock; }
// Up to this many measurements per sample, the covariance step is the fused pass of
// symmetric_rank_update.hpp and W a column loop; beyond, Eigen's blocked SYRK (after the prediction
// on its own) and TRSM. At a low rank the update is bound by the passes over P and SYRK's packing
// of W costs more than it saves; at a high rank it is bound by multiply-adds, where SYRK's packed
// register-blocked kernel is the faster. Measured (README "Per-tick latency", linear RLS, same run):
// fused 0.86-0.95x of SYRK at 3 and 7 measurements, 1.19x at 14 and 28.
constexpr int kFusedMaxRank = 8;
}  // namespace

template <int N, int M>
BasicKalmanUpdate<N, M>::BasicKalmanUpdate(int n, int m, const Eigen::VectorXd& initial_std,
                                           const KalmanOptions& options)
    : options_(options), llt_(m > 0 ? m : 1) {
  if (n < 1 || m < 1) throw std::invalid_argument("Kalman update: needs at least one parameter and one measurement");
  if (!kDynamic && (n != N || m != M)) {
    throw std::invalid_argument("Kalman update: sizes " + std::to_string(n) + " x " + std::to_string(m) +
                                " for an update of fixed size " + std::to_string(N) + " x " + std::to_string(M));
  }
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
  n_ = n;
  m_ = m;
  S_.resize(m, m);
  z_.resize(m);
  dx_ = VectorN::Zero(n);
  if constexpr (kDynamic) {
    // P, H^T and P H^T padded with zeros to whole blocks of the span product (the padding stays zero).
    P_ = Eigen::MatrixXd::Zero(RoundUpToBlock(n), RoundUpToBlock(n));
    Ht_ = Eigen::MatrixXd::Zero(RoundUpToBlock(n), RoundUpToBlock(m));
    HtD_ = Eigen::MatrixXd::Zero(RoundUpToBlock(n), RoundUpToBlock(m));
    PHt_ = Eigen::MatrixXd::Zero(RoundUpToBlock(n), RoundUpToBlock(m));
    W_ = Eigen::MatrixXd::Zero(RoundUpToBlock(n), m);
    first_.resize(m);
    end_.resize(m);
  } else {  // the padding rows stay zero
    Ht_.setZero();
    HtD_.setZero();
    PHt_.setZero();
    W_.setZero();
  }
  cap_ = VectorS::Zero(P_.rows());
  cap_.head(n) = o.max_variance_factor * initial_std.array().square();
  forget_ = VectorS::Ones(P_.rows());
  noise_ = VectorS::Zero(P_.rows());
  P_.setZero();
  P_.diagonal().head(n) = initial_std.array().square();
}

template <int N, int M>
void BasicKalmanUpdate<N, M>::ChoosePrediction() {
  // Selective forgetting (D_ii = lambda^-1/2 below the cap, 1 above) and process noise below the
  // cap (tested after forgetting), from the diagonal of the last posterior.
  const double f = options_.forgetting < 1.0 ? 1.0 / std::sqrt(options_.forgetting) : 1.0;
  const double q = options_.process_noise;
  for (int i = 0; i < n_; ++i) {
    forget_[i] = P_(i, i) < cap_[i] ? f : 1.0;
    noise_[i] = q > 0.0 && P_(i, i) * (forget_[i] * forget_[i]) < cap_[i] ? q : 0.0;
  }
}

template <int N, int M>
template <class Matrix>
void BasicKalmanUpdate<N, M>::ApplyPrediction(Matrix& P) const {
  // Elementwise as the fused pass of Commit() scales (x * (d_i d_j)), on the lower triangle where
  // only that is kept.
  const int n = n_;
  if constexpr (kDynamic) {
    for (int j = 0; j < n; ++j) P.col(j).segment(j, n - j).array() *= forget_[j] * forget_.segment(j, n - j).array();
  } else {
    P.array() *= (forget_ * forget_.transpose()).array();
  }
  P.diagonal().head(n) += noise_.head(n);
}

template <int N, int M>
void BasicKalmanUpdate<N, M>::ResetCovariance() {
  P_.setZero();
  P_.diagonal().head(n_) = cap_.head(n_) / options_.max_variance_factor;
  forget_.setOnes();
  noise_.setZero();
  scaled_ = pending_ = false;
}

template <int N, int M>
UpdateStatus BasicKalmanUpdate<N, M>::Step(const MatrixH& H, const VectorM& r) {
  INERTIAL_ASSERT(H.rows() == m_ && H.cols() == n_ && r.size() == m_);
  r_ = &r;
  const int m = m_;
  if (pending_) ApplyPrediction(P_);  // the last Step was not committed: its prediction still holds
  pending_ = false;
  scaled_ = options_.forgetting < 1.0 || options_.process_noise > 0.0;
  if (scaled_) {
    ChoosePrediction();
    pending_ = true;
  }
  Transpose(H);
  Predict();
  if (!Factor(H, 1.0)) return UpdateStatus::kNumerical;
  normalized_innovation_ = std::sqrt(z_.squaredNorm() / m);
  if (normalized_innovation_ > options_.gate && !tracking_change_) {
    if (++consecutive_outliers_ <= options_.max_consecutive_outliers) return UpdateStatus::kOutlier;
    // A persistent change, not an outlier (a payload picked up): inflate P once and take every
    // sample until the innovations are back inside the gate.
    tracking_change_ = true;
    ++changes_;
    // Everything may have changed: back to the initial uncertainty about the current estimate.
    ResetCovariance();
    Predict();
    if (!Factor(H, 1.0)) return UpdateStatus::kNumerical;
  } else if (normalized_innovation_ <= options_.gate) {
    consecutive_outliers_ = 0;
    tracking_change_ = false;
  }
  const double e = std::sqrt(z_.squaredNorm() / m);
  if (e > options_.huber && !Factor(H, options_.huber / e)) return UpdateStatus::kNumerical;
  // W = P H^T L^-T: W L^T = P H^T, a triangular solve from the right, column by column (m small:
  // axpys over n, no packing as in Eigen's blocked solve; of dynamic W all padded rows, which stay 0).
  if constexpr (!kDynamic) {
    // W was formed by Factor().
  } else if (m <= kFusedMaxRank) {
    const auto& L = llt_.matrixLLT();
    for (int j = 0; j < m; ++j) {
      W_.col(j) = PHt_.col(j).head(W_.rows());
      for (int k = 0; k < j; ++k) W_.col(j) -= L(j, k) * W_.col(k);
      W_.col(j) /= L(j, j);
    }
  } else {  // blocked, in blocks of m columns that fit the stack: no allocation
    W_ = PHt_.topLeftCorner(W_.rows(), m);
    llt_.matrixU().template solveInPlace<Eigen::OnTheRight>(W_);
  }
  if constexpr (kDynamic) {
    dx_.noalias() = W_.topRows(n_) * z_;
  } else {
    dx_.noalias() = W_.template topRows<N>() * z_;
  }
  if (!dx_.allFinite() || !W_.allFinite()) return UpdateStatus::kNumerical;
  const double largest = dx_.template lpNorm<Eigen::Infinity>();
  step_scale_ = largest > options_.max_step ? options_.max_step / largest : 1.0;
  dx_ *= step_scale_;
  return UpdateStatus::kAccepted;
}

template <int N, int M>
void BasicKalmanUpdate<N, M>::Transpose(const MatrixH& H) {
  // H^T, so that every measurement's row is a contiguous column, and each row's span of nonzero
  // columns [first, end): a joint's torque depends only on the bodies it carries and its own
  // effects, so a robot's regressor is block-triangular and the spans are what the products need.
  if constexpr (!kDynamic) {
    Ht_.template topRows<N>() = H.transpose();
  } else {
    Ht_.topLeftCorner(n_, m_) = H.transpose();
    for (int i = 0; i < m_; ++i) NonzeroSpan(Ht_.col(i).head(n_), &first_[i], &end_[i]);
  }
}

template <int N, int M>
void BasicKalmanUpdate<N, M>::Predict() {
  if constexpr (kDynamic) {
    // PHt = P H^T from the lower triangle of P, kSpanBlock measurements at a time over the union
    // of their spans rounded out to whole blocks (symmetric_span_product.hpp).
    // With a prediction: P_pred H^T = D (P (D H^T)) + Q H^T.
    if (scaled_) HtD_ = forget_.asDiagonal() * Ht_;
    const Eigen::MatrixXd& G = scaled_ ? HtD_ : Ht_;
    for (int g0 = 0; g0 < PHt_.cols(); g0 += kSpanBlock) {
      int c = n_, e = 0;
      for (int i = g0; i < std::min(g0 + kSpanBlock, m_); ++i) {
        if (first_[i] < end_[i]) {
          c = std::min(c, first_[i]);
          e = std::max(e, end_[i]);
        }
      }
      if (c >= e) {  // no measurement of the group depends on anything
        PHt_.middleCols(g0, kSpanBlock).setZero();
        continue;
      }
      SymmetricSpanProduct(P_, G.middleCols(g0, kSpanBlock), c / kSpanBlock * kSpanBlock, RoundUpToBlock(e),
                           PHt_.middleCols(g0, kSpanBlock));
    }
    if (scaled_) PHt_ = forget_.asDiagonal() * PHt_ + noise_.asDiagonal() * Ht_;
  } else if (scaled_) {  // fixed sizes: unrolled over whole packets
    HtD_ = forget_.asDiagonal() * Ht_;
    PHt_.noalias() = P_.lazyProduct(HtD_);
    PHt_ = forget_.asDiagonal() * PHt_ + noise_.asDiagonal() * Ht_;
  } else {
    PHt_.noalias() = P_.lazyProduct(Ht_);
  }
}

template <int N, int M>
bool BasicKalmanUpdate<N, M>::Factor(const MatrixH& H, double weight) {
  // S = H P H^T + (sigma^2 / weight) 1, lower triangle only (what the Cholesky factorization
  // reads), each row of H over its span.
  if constexpr (kDynamic) {
    for (int i = 0; i < m_; ++i) {
      const int c = first_[i], l = end_[i] - first_[i];
      if (l <= 0) {
        S_.row(i).head(i + 1).setZero();
      } else {
        S_.row(i).head(i + 1).noalias() = Ht_.col(i).segment(c, l).transpose().lazyProduct(PHt_.block(c, 0, l, i + 1));
      }
    }
  } else {
    // Fixed sizes: S from independent dot products, its Cholesky factor by hand (unrolled; no
    // call into Eigen's generic factorization), then z = L^-1 r and W = P H^T L^-T.
    (void)H;
    S_.noalias() = Ht_.transpose().lazyProduct(PHt_);
    S_.diagonal().array() += options_.measurement_sigma * options_.measurement_sigma / weight;
    Eigen::Matrix<double, M, M>& L = S_;  // in place, lower triangle
    VectorM inv;
    for (int j = 0; j < M; ++j) {
      double d = L(j, j);
      for (int k = 0; k < j; ++k) d -= L(j, k) * L(j, k);
      if (!(d > 0.0)) return false;
      L(j, j) = std::sqrt(d);
      inv[j] = 1.0 / L(j, j);
      for (int i = j + 1; i < M; ++i) {
        double e = L(i, j);
        for (int k = 0; k < j; ++k) e -= L(i, k) * L(j, k);
        L(i, j) = e * inv[j];
      }
    }
    for (int j = 0; j < M; ++j) {
      double zj = (*r_)[j];
      VectorS a = PHt_.col(j);
      for (int k = 0; k < j; ++k) {
        zj -= L(j, k) * z_[k];
        a -= L(j, k) * W_.col(k);
      }
      z_[j] = zj * inv[j];
      W_.col(j) = a * inv[j];
    }
    return z_.allFinite();
  }
  S_.diagonal().array() += options_.measurement_sigma * options_.measurement_sigma / weight;
  llt_.compute(S_);
  if (llt_.info() != Eigen::Success) return false;
  z_ = *r_;
  llt_.matrixL().solveInPlace(z_);
  return z_.allFinite();
}

template <int N, int M>
void BasicKalmanUpdate<N, M>::Commit(double fraction) {
  // A step cut to a fraction of the Kalman step used only that fraction of the sample's
  // information: the covariance shrinks by as much (P - f W W^T stays positive definite for f <= 1).
  // With the sample's prediction: P <- D P D + Q - f W W^T (D = 1, Q = 0 without one).
  const double f = fraction * step_scale_;
  if constexpr (kDynamic) {
    // The lower triangle only: prediction and downdate in one pass (symmetric_rank_update.hpp) at
    // a low rank, the prediction and then Eigen's SYRK (its blocks of m columns fit the stack: no
    // allocation) at a high one (kFusedMaxRank).
    if (m_ <= kFusedMaxRank) {
      ScaledSymmetricRankUpdate(P_, forget_, W_, f);
      if (scaled_) P_.diagonal().head(n_) += noise_.head(n_);
    } else {
      if (scaled_) ApplyPrediction(P_);
      P_.topLeftCorner(n_, n_).template selfadjointView<Eigen::Lower>().rankUpdate(W_.topRows(n_), -f);
    }
  } else {
    // Fixed sizes: P in full, unrolled, and kept exactly symmetric (the lower triangle mirrored),
    // so that a covariance saved (Covariance()) and restored continues bit for bit.
    if (scaled_) ApplyPrediction(P_);
    P_.noalias() -= (f * W_).lazyProduct(W_.transpose());
    P_.template triangularView<Eigen::StrictlyUpper>() = P_.transpose();
  }
  pending_ = false;
}

template <int N, int M>
Eigen::MatrixXd BasicKalmanUpdate<N, M>::Covariance() const {
  if (pending_) {  // exactly what the next Step() will start from
    Eigen::Matrix<double, kRows, kRows> P = P_;
    ApplyPrediction(P);
    return P.topLeftCorner(n_, n_).template selfadjointView<Eigen::Lower>();
  }
  return P_.topLeftCorner(n_, n_).template selfadjointView<Eigen::Lower>();
}

template <int N, int M>
bool BasicKalmanUpdate<N, M>::SetCovariance(const Eigen::MatrixXd& P) {
  if (P.rows() != n_ || P.cols() != n_ || !P.allFinite()) return false;
  // Exactly (of a dynamic P the lower triangle is used), so that a restored estimator continues bit for bit.
  P_.topLeftCorner(n_, n_) = P;
  pending_ = false;
  // The change detector's run of outliers is not part of a saved state: a restored estimator starts
  // a fresh one, so that what follows depends on the state restored alone, not on the samples this
  // estimator saw before (a run of them would otherwise carry over into the restored one).
  consecutive_outliers_ = 0;
  tracking_change_ = false;
  return true;
}

template class BasicKalmanUpdate<Eigen::Dynamic, Eigen::Dynamic>;
template class BasicKalmanUpdate<10, 6>;

}  // namespace inertial
