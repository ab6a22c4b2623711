#include "inertial/estimation/online/gradient_estimator.hpp"

#include "inertial/estimation/online/symmetric_rank_update.hpp"
#include "inertial/estimation/online/symmetric_span_product.hpp"

#include <Eigen/Eigenvalues>

#include <cmath>
#include <stdexcept>

namespace inertial {

GradientEstimator::GradientEstimator(ParameterLayout layout, int num_measurements, const Eigen::VectorXd& x0,
                                     const Eigen::VectorXd& scale, const GradientOptions& options)
    : RecursiveEstimator(layout.num_features(), num_measurements),
      layout_(std::move(layout)),
      options_(options),
      x_(x0) {
  const int n = layout_.num_parameters();
  if (num_measurements < 1) throw std::invalid_argument("gradient law: needs at least one measurement");
  if (x0.size() != n || !x0.allFinite()) throw std::invalid_argument("gradient law: x0 must be " + std::to_string(n) + " finite numbers");
  if (scale.size() != n || !scale.allFinite() || !(scale.array() > 0).all()) {
    throw std::invalid_argument("gradient law: scale must be " + std::to_string(n) + " positive numbers");
  }
  if (!(options.gain > 0 && options.gain < 2)) throw std::invalid_argument("gradient law: gain must be in (0, 2)");
  if (!(options.measurement_sigma > 0) || !(options.huber > 0) || !(options.gate > 0) || !(options.max_step > 0) ||
      !(options.max_abs_parameter > 0) || options.max_consecutive_outliers < 0) {
    throw std::invalid_argument("gradient law: options must be positive");
  }
  if (!options.frozen_bodies.empty() && options.frozen_bodies.size() != layout_.bodies().size()) {
    throw std::invalid_argument("gradient law: frozen_bodies must name every body (" + std::to_string(layout_.bodies().size()) + ")");
  }
  const int F = layout_.num_features();
  padded_ = (F + kSpanBlock - 1) / kSpanBlock * kSpanBlock;
  gamma_ = scale.array().square();
  w_.resize(F);
  dw_.resize(F);
  r_.resize(num_measurements);
  dx_.resize(n);
  x_next_.resize(n);
  S_ = Eigen::MatrixXd::Zero(padded_, padded_);
  At_ = Eigen::MatrixXd::Zero(padded_, num_measurements);
  s_ = Eigen::VectorXd::Zero(F);
  ones_ = Eigen::VectorXd::Ones(padded_);
  g_ = Eigen::VectorXd::Zero(padded_);
  wp_ = Eigen::VectorXd::Zero(padded_);
  Sdw_ = Eigen::VectorXd::Zero(padded_);
  direction_ = Eigen::VectorXd::Zero(padded_);
  for (const BodyBlock& b : layout_.bodies()) {
    Matrix4 U0;
    if (!UpperCholesky(b.map.reference_pseudo_inertia(), &U0)) {
      throw std::invalid_argument("gradient law: a body's prior has no Cholesky factor");
    }
    reference_factor_.push_back(U0);
  }
  factor_.resize(layout_.bodies().size(), Matrix4::Identity());
  exponent_.resize(layout_.bodies().size(), Matrix4::Zero());
  direction_z_.resize(layout_.bodies().size(), Matrix4::Zero());
  direction_d_.resize(layout_.bodies().size(), Matrix4::Zero());
  previous_d_.resize(layout_.bodies().size(), Matrix4::Zero());
  Adw_ = Eigen::VectorXd::Zero(num_measurements);
  previous_g_ = Eigen::VectorXd::Zero(F);
  previous_dw_ = Eigen::VectorXd::Zero(F);
  previous_dx_ = Eigen::VectorXd::Zero(n);
}

namespace {
// expm(X) of a symmetric 4 x 4 X by scaling and squaring: X / 2^k with |X / 2^k|_F <= 1/8, its
// Taylor series to order 10 (remainder below (1/8)^11 / 11! ~ 3e-18 of the identity's size), then
// squared k times. Cheaper than an eigen-decomposition (Eigen's iterative 4 x 4 solver took 40 % of
// the body's tick: 2.56 us, 1.47 without); symmetric and positive definite (a square of a symmetric
// matrix near the identity). The step bound (max_step 0.1) keeps k = 0 by default.
Matrix4 SymmetricExponential(const Matrix4& X) {
  const double norm = X.norm();
  int k = 0;
  while (norm > 0.125 * std::ldexp(1.0, k) && k < 60) ++k;
  const Matrix4 Y = std::ldexp(1.0, -k) * X;
  Matrix4 E = Matrix4::Identity(), term = Matrix4::Identity();
  for (int i = 1; i <= 10; ++i) {
    term = (term * Y) / static_cast<double>(i);
    E += term;
  }
  for (int i = 0; i < k; ++i) E = (E * E).eval();
  return 0.5 * (E + E.transpose());
}

// dw/dx_k of an effect parameter k of block s, into column d (F): nonzero at the block's features.
void EffectDirection(const ScalarBlock& s, int k, const Eigen::VectorXd& x, Eigen::VectorXd& d) {
  const double e0 = std::exp(x[s.parameter]);
  switch (s.map) {
    case ScalarMap::kLinear: d[s.feature] = 1.0; break;
    case ScalarMap::kExponential: d[s.feature] = e0; break;
    case ScalarMap::kSpring:  // w = [e^x0, e^x0 x1]
      if (k == s.parameter) {
        d[s.feature] = e0;
        d[s.feature + 1] = e0 * x[s.parameter + 1];
      } else {
        d[s.feature + 1] = e0;
      }
      break;
  }
}
}  // namespace

UpdateStatus GradientEstimator::Apply(const Eigen::MatrixXd& A, const Eigen::VectorXd& y) {
  layout_.Coefficients(x_, w_);
  r_ = y;
  r_.noalias() -= A * w_;
  const double sigma = options_.measurement_sigma;
  const double e = r_.norm() / (sigma * std::sqrt(static_cast<double>(r_.size())));
  if (!std::isfinite(e)) return UpdateStatus::kNumerical;
  if (e > options_.gate) {
    if (++consecutive_outliers_ <= options_.max_consecutive_outliers) return UpdateStatus::kOutlier;
    // A run longer than max_consecutive_outliers is a change of the system (a payload picked up):
    // the memory starts over from the current estimate, as the online fit's statistics do.
    consecutive_outliers_ = 0;
    S_.setZero();
    s_.setZero();
    has_previous_ = false;
    ++changes_;
  } else {
    consecutive_outliers_ = 0;
  }
  const double weight = e > options_.huber ? options_.huber / e : 1.0;
  // The objective with this sample, S' = S + weight A^T A, s' = s + weight A^T y, used without
  // changing S and s until the step is taken (a refused sample leaves them as they were):
  // g = s' - S' w = (s - S w) + weight A^T r, the negative gradient of L(w) = w^T S' w / 2 - s'^T w.
  const int F = layout_.num_features();
  wp_.head(F) = w_;
  g_.noalias() = S_.selfadjointView<Eigen::Lower>() * wp_;
  g_ = -g_;
  g_.head(F) += s_;
  g_.head(F).noalias() += weight * (A.transpose() * r_);

  // The natural gradient z: per body Z_b = J T*(g_b) J = F S_b F^T, S_b = F^T T*(g_b) F (bodies that
  // share a feature block, a payload on its link, add their pi into it); per effect parameter
  // Gamma (dw/dx)^T g. dw: z's first-order change of w.
  dw_.setZero();
  const std::vector<BodyBlock>& bodies = layout_.bodies();
  for (size_t b = 0; b < bodies.size(); ++b) {
    const BodyBlock& block = bodies[b];
    direction_z_[b].setZero();
    if (!options_.frozen_bodies.empty() && options_.frozen_bodies[b]) continue;
    const Matrix4& Fb = factor_[b] = LogCholeskyFactor(x_.segment<10>(block.parameter)) * reference_factor_[b];
    const Matrix4 Sb = Fb.transpose() * PseudoInertiaGradient(g_.segment<10>(block.feature)) * Fb;
    const Matrix4 Z = Fb * Sb * Fb.transpose();
    direction_z_[b] = 0.5 * (Z + Z.transpose());  // exactly symmetric: the state keeps its upper triangle
    dw_.segment<10>(block.feature) += PiFromPseudoInertia(direction_z_[b]);
  }
  dx_.setZero();
  for (const ScalarBlock& sb : layout_.scalars()) {
    for (int k = sb.parameter; k < sb.parameter + sb.size(); ++k) {
      direction_.setZero();
      EffectDirection(sb, k, x_, direction_);
      const double d = gamma_[k] * direction_.head(F).dot(g_.head(F));
      dx_[k] = d;
      dw_ += d * direction_.head(F);
    }
  }
  // Conjugate directions (Polak-Ribiere+, preconditioned by the natural metric): d = z + beta d_prev,
  // beta = max(0, z . (g - g_prev) / (z_prev . g_prev)); a d that would not descend (the objective
  // changed too much since) restarts along z.
  const double zg = g_.head(F).dot(dw_);
  double beta = 0.0;
  if (has_previous_ && previous_zg_ > 0) beta = std::max(0.0, (zg - dw_.dot(previous_g_)) / previous_zg_);
  if (beta > 0 && g_.head(F).dot(dw_ + beta * previous_dw_) <= 0) beta = 0.0;
  dw_ += beta * previous_dw_;
  dx_ += beta * previous_dx_;
  // The exact line search of the quadratic along dw: step = gain (g . dw) / (dw^T S' dw), with
  // S' dw = S dw + weight A^T (A dw).
  wp_.head(F) = dw_;
  Sdw_.noalias() = S_.selfadjointView<Eigen::Lower>() * wp_;
  Adw_.noalias() = A * dw_;
  Sdw_.head(F).noalias() += weight * (A.transpose() * Adw_);
  const double gd = g_.head(F).dot(dw_), dSd = wp_.dot(Sdw_);
  if (!std::isfinite(gd) || !std::isfinite(dSd)) return UpdateStatus::kNumerical;
  // Per body the J-space direction D_b = Z_b + beta D_b,prev, in the factor's frame F^-1 D_b F^-T
  // (= S_b when beta = 0); its size and |dx|_inf bound the step.
  double largest = dx_.lpNorm<Eigen::Infinity>();
  for (size_t b = 0; b < bodies.size(); ++b) {
    direction_d_[b] = direction_z_[b] + beta * previous_d_[b];
    exponent_[b].setZero();
    if (!options_.frozen_bodies.empty() && options_.frozen_bodies[b]) continue;
    const Matrix4& Fb = factor_[b];
    const Matrix4 left = Fb.triangularView<Eigen::Upper>().solve(direction_d_[b]);
    const Matrix4 X = Fb.triangularView<Eigen::Upper>().solve(left.transpose());  // F^-1 (F^-1 D)^T
    exponent_[b] = 0.5 * (X + X.transpose());
    largest = std::max(largest, exponent_[b].norm());
  }
  double step = gd > 0 && dSd > 0 ? options_.gain * gd / dSd : 0.0;
  if (step * largest > options_.max_step) step = options_.max_step / largest;

  // The step: J+ = F expm(step X_b) F^T per body (positive definite exactly), x + step dx for effects.
  x_next_ = x_;
  for (size_t b = 0; b < bodies.size() && step > 0; ++b) {
    const BodyBlock& block = bodies[b];
    if (!options_.frozen_bodies.empty() && options_.frozen_bodies[b]) continue;
    const Matrix4 E = SymmetricExponential(step * exponent_[b]);
    const Matrix4& Fb = factor_[b];
    Vector10 theta;
    if (!block.map.FromPi(PiFromPseudoInertia(Fb * E * Fb.transpose()), &theta)) return UpdateStatus::kNumerical;
    x_next_.segment<10>(block.parameter) = theta;
  }
  x_next_ += step * dx_;
  for (int i = 0; i < x_next_.size(); ++i) {
    if (!(std::abs(x_next_[i]) <= options_.max_abs_parameter)) return UpdateStatus::kNumerical;
  }
  // Taken: the estimate, the sample into the memory, the direction remembered.
  x_.swap(x_next_);
  At_.topRows(F) = std::sqrt(weight) * A.transpose();
  ScaledSymmetricRankUpdate(S_, ones_, At_, -1.0);
  s_.noalias() += weight * (A.transpose() * y);
  has_previous_ = true;
  previous_zg_ = zg;
  previous_g_ = g_.head(F);  // allocation-free: sized at construction
  previous_dw_ = dw_;
  previous_dx_ = dx_;
  for (size_t b = 0; b < bodies.size(); ++b) previous_d_[b] = direction_d_[b];
  return UpdateStatus::kAccepted;
}

bool GradientEstimator::SetParameters(const Eigen::VectorXd& x, const Eigen::MatrixXd&, std::string*) {
  x_ = x;
  consecutive_outliers_ = 0;  // the run of outliers is not part of a state: a restore starts a fresh one
  return true;
}

void GradientEstimator::SaveExtra(EstimatorState* state) const {
  const int F = layout_.num_features(), n = layout_.num_parameters();
  const int B = static_cast<int>(layout_.bodies().size());
  state->statistics = Eigen::MatrixXd::Zero(F + 1, F + 1);
  state->statistics.topLeftCorner(F, F) = S_.topLeftCorner(F, F).selfadjointView<Eigen::Lower>();
  state->statistics.col(F).head(F) = s_;
  state->statistics.row(F).head(F) = s_.transpose();
  // [g_prev (F), dw_prev (F), dx_prev (n), each body's D_prev (its upper triangle row by row, 10 B),
  // z_prev . g_prev, has_previous]
  state->directions.resize(DirectionsSize());
  state->directions.head(F) = previous_g_;
  state->directions.segment(F, F) = previous_dw_;
  state->directions.segment(2 * F, n) = previous_dx_;
  for (int b = 0; b < B; ++b) {
    int k = 2 * F + n + 10 * b;
    for (int i = 0; i < 4; ++i) {
      for (int j = i; j < 4; ++j) state->directions[k++] = previous_d_[b](i, j);
    }
  }
  state->directions[2 * F + n + 10 * B] = previous_zg_;
  state->directions[2 * F + n + 10 * B + 1] = has_previous_ ? 1.0 : 0.0;
}

int GradientEstimator::DirectionsSize() const {
  return 2 * layout_.num_features() + layout_.num_parameters() + 10 * static_cast<int>(layout_.bodies().size()) + 2;
}

bool GradientEstimator::CheckExtra(const EstimatorState& state, std::string* why) const {
  const int F = layout_.num_features();
  if (state.statistics.size() > 0) {
    const Eigen::MatrixXd& M = state.statistics;
    if (M.rows() != F + 1 || M.cols() != F + 1 || !M.allFinite()) {
      if (why != nullptr) *why = "its statistics are not " + std::to_string(F + 1) + " x " + std::to_string(F + 1) + " finite numbers";
      return false;
    }
    // Sums of squares: symmetric, positive semidefinite (to rounding).
    const double scale = std::max(1.0, M.cwiseAbs().maxCoeff());
    const bool symmetric = (M - M.transpose()).cwiseAbs().maxCoeff() <= 1e-9 * scale;
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(M.topLeftCorner(F, F), Eigen::EigenvaluesOnly);
    if (!symmetric || eig.info() != Eigen::Success || eig.eigenvalues().minCoeff() < -1e-9 * scale) {
      if (why != nullptr) *why = "its statistics are not a symmetric positive semidefinite sum of squares";
      return false;
    }
  }
  if (state.directions.size() > 0 && (state.directions.size() != DirectionsSize() || !state.directions.allFinite())) {
    if (why != nullptr) *why = "its directions are not " + std::to_string(DirectionsSize()) + " finite numbers";
    return false;
  }
  return true;
}

void GradientEstimator::RestoreExtra(const EstimatorState& state) {
  // What a state does not carry starts empty: no statistics, no previous direction.
  const int F = layout_.num_features(), n = layout_.num_parameters();
  const int B = static_cast<int>(layout_.bodies().size());
  S_.setZero();
  s_.setZero();
  if (state.statistics.size() > 0) {
    S_.topLeftCorner(F, F) = state.statistics.topLeftCorner(F, F);
    s_ = state.statistics.col(F).head(F);
  }
  has_previous_ = false;
  previous_zg_ = 0.0;
  previous_g_.setZero();
  previous_dw_.setZero();
  previous_dx_.setZero();
  for (Matrix4& d : previous_d_) d.setZero();
  if (state.directions.size() > 0) {
    previous_g_ = state.directions.head(F);
    previous_dw_ = state.directions.segment(F, F);
    previous_dx_ = state.directions.segment(2 * F, n);
    for (int b = 0; b < B; ++b) {
      int k = 2 * F + n + 10 * b;
      for (int i = 0; i < 4; ++i) {
        for (int j = i; j < 4; ++j) previous_d_[b](i, j) = previous_d_[b](j, i) = state.directions[k++];
      }
    }
    previous_zg_ = state.directions[2 * F + n + 10 * B];
    has_previous_ = state.directions[2 * F + n + 10 * B + 1] != 0.0;
  }
}

}  // namespace inertial
