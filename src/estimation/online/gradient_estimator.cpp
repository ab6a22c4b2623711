#include "inertial/estimation/online/gradient_estimator.hpp"

#include "inertial/estimation/online/symmetric_rank_update.hpp"
#include "inertial/estimation/online/symmetric_span_product.hpp"

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
  previous_g_ = Eigen::VectorXd::Zero(F);
  previous_dw_ = Eigen::VectorXd::Zero(F);
  previous_dx_ = Eigen::VectorXd::Zero(n);
}

namespace {
// expm(X) of a symmetric 4 x 4 X by scaling and squaring: X / 2^k with |X / 2^k|_F <= 1/8, its
// Taylor series to order 10 (remainder below (1/8)^11 / 11! ~ 2e-18 of the identity's size), then
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
    consecutive_outliers_ = 0;
  } else {
    consecutive_outliers_ = 0;
  }
  const double weight = e > options_.huber ? options_.huber / e : 1.0;
  // The memory: S += weight A^T A, s += weight A^T y (the statistics of every sample so far).
  const int F = layout_.num_features();
  At_.topRows(F) = std::sqrt(weight) * A.transpose();
  ScaledSymmetricRankUpdate(S_, ones_, At_, -1.0);
  s_.noalias() += weight * (A.transpose() * y);
  const auto refuse = [&] {  // the memory as it was: the sample changes nothing
    ScaledSymmetricRankUpdate(S_, ones_, At_, 1.0);
    s_.noalias() -= weight * (A.transpose() * y);
    return UpdateStatus::kNumerical;
  };
  // The negative gradient of L(w) = w^T S w / 2 - s^T w at w: g = s - S w.
  wp_.head(F) = w_;
  g_.noalias() = S_.selfadjointView<Eigen::Lower>() * wp_;
  g_ = -g_;
  g_.head(F) += s_;

  // The direction: per body S_b = F^T T*(g_b) F (the natural gradient J G J = F S_b F^T), per
  // effect parameter Gamma dw/dx^T g; dw = its first-order change of w per unit step.
  dw_.setZero();
  double largest = 0.0;
  const std::vector<BodyBlock>& bodies = layout_.bodies();
  for (size_t b = 0; b < bodies.size(); ++b) {
    const BodyBlock& block = bodies[b];
    if (!options_.frozen_bodies.empty() && options_.frozen_bodies[b]) {
      exponent_[b].setZero();
      continue;
    }
    const Vector10 g = g_.segment<10>(block.feature);
    const Matrix4& Fb = factor_[b] = LogCholeskyFactor(x_.segment<10>(block.parameter)) * reference_factor_[b];
    const Matrix4 Sb = Fb.transpose() * PseudoInertiaGradient(g) * Fb;
    exponent_[b] = Sb;
    dw_.segment<10>(block.feature) = PiFromPseudoInertia(Fb * Sb * Fb.transpose());
    largest = std::max(largest, Sb.norm());
  }
  dx_.setZero();
  for (const ScalarBlock& sb : layout_.scalars()) {
    for (int k = sb.parameter; k < sb.parameter + sb.size(); ++k) {
      direction_.setZero();
      EffectDirection(sb, k, x_, direction_);
      const double d = gamma_[k] * direction_.head(F).dot(g_.head(F));
      dx_[k] = d;
      dw_ += d * direction_.head(F);
      largest = std::max(largest, std::abs(d));
    }
  }
  // Conjugate directions (Polak-Ribiere+, preconditioned by the natural metric): the direction
  // d = z + beta d_prev, z the natural gradient (dw_ in w, F S_b F^T in J), beta =
  // max(0, z . (g - g_prev) / (z_prev . g_prev)).
  const double zg = g_.head(F).dot(dw_);
  double beta = 0.0;
  if (has_previous_ && previous_zg_ > 0) beta = std::max(0.0, (zg - dw_.dot(previous_g_)) / previous_zg_);
  // A conjugate direction that does not descend (the objective changed too much since) restarts
  // along z.
  if (beta > 0 && g_.head(F).dot(dw_ + beta * previous_dw_) <= 0) beta = 0.0;
  dw_ += beta * previous_dw_;  // a body's part is pi of its J-space direction (linear, one to one)
  dx_ += beta * previous_dx_;
  // The exact line search of the quadratic along dw: step = (g . dw) / (dw^T S dw), times gain.
  wp_.head(F) = dw_;
  Sdw_.noalias() = S_.selfadjointView<Eigen::Lower>() * wp_;
  const double gd = g_.head(F).dot(dw_), dSd = wp_.dot(Sdw_);
  if (!std::isfinite(gd) || !std::isfinite(dSd)) return refuse();
  largest = dx_.lpNorm<Eigen::Infinity>();
  for (size_t b = 0; b < bodies.size(); ++b) {
    if (!options_.frozen_bodies.empty() && options_.frozen_bodies[b]) continue;
    const Matrix4& Fb = factor_[b];
    // F^-1 D F^-T: the direction D = J(dw_b) in the factor's frame (= S_b when beta = 0).
    const Matrix4 left = Fb.triangularView<Eigen::Upper>().solve(PseudoInertiaFromPi(dw_.segment<10>(bodies[b].feature)));
    const Matrix4 X = Fb.triangularView<Eigen::Upper>().solve(left.transpose());  // F^-1 (F^-1 D)^T, symmetric
    exponent_[b] = 0.5 * (X + X.transpose());
    largest = std::max(largest, exponent_[b].norm());
  }
  double step = gd > 0 && dSd > 0 ? options_.gain * gd / dSd : 0.0;
  if (step * largest > options_.max_step) step = options_.max_step / largest;

  // The step: J+ = F expm(step S_b) F^T per body (positive definite exactly), x + step dx for effects.
  x_next_ = x_;
  for (size_t b = 0; b < bodies.size() && step > 0; ++b) {
    const BodyBlock& block = bodies[b];
    if (!options_.frozen_bodies.empty() && options_.frozen_bodies[b]) continue;
    const Matrix4 E = SymmetricExponential(step * exponent_[b]);
    const Matrix4& Fb = factor_[b];
    Vector10 theta;
    if (!block.map.FromPi(PiFromPseudoInertia(Fb * E * Fb.transpose()), &theta)) return refuse();
    x_next_.segment<10>(block.parameter) = theta;
  }
  x_next_ += step * dx_;
  for (int i = 0; i < x_next_.size(); ++i) {
    if (!(std::abs(x_next_[i]) <= options_.max_abs_parameter)) return refuse();
  }
  has_previous_ = true;
  previous_zg_ = zg;
  previous_g_ = g_.head(F);  // allocation-free: sized at construction
  previous_dw_ = dw_;
  previous_dx_ = dx_;
  x_.swap(x_next_);
  return UpdateStatus::kAccepted;
}

bool GradientEstimator::SetParameters(const Eigen::VectorXd& x, const Eigen::MatrixXd&, std::string*) {
  x_ = x;
  consecutive_outliers_ = 0;  // the run of outliers is not part of a state: a restore starts a fresh one
  return true;
}

void GradientEstimator::SaveExtra(EstimatorState* state) const {
  const int F = layout_.num_features(), n = layout_.num_parameters();
  state->statistics = Eigen::MatrixXd::Zero(F + 1, F + 1);
  state->statistics.topLeftCorner(F, F) = S_.topLeftCorner(F, F).selfadjointView<Eigen::Lower>();
  state->statistics.col(F).head(F) = s_;
  state->statistics.row(F).head(F) = s_.transpose();
  // [g_prev, dw_prev, dx_prev, z_prev . g_prev, has_previous]
  state->directions.resize(2 * F + n + 2);
  state->directions << previous_g_, previous_dw_, previous_dx_, previous_zg_, has_previous_ ? 1.0 : 0.0;
}

bool GradientEstimator::CheckExtra(const EstimatorState& state, std::string* why) const {
  const int F = layout_.num_features(), n = layout_.num_parameters();
  if (state.statistics.size() > 0 &&
      (state.statistics.rows() != F + 1 || state.statistics.cols() != F + 1 || !state.statistics.allFinite())) {
    if (why != nullptr) *why = "its statistics are not " + std::to_string(F + 1) + " x " + std::to_string(F + 1) + " finite numbers";
    return false;
  }
  if (state.directions.size() > 0 && (state.directions.size() != 2 * F + n + 2 || !state.directions.allFinite())) {
    if (why != nullptr) *why = "its directions are not " + std::to_string(2 * F + n + 2) + " finite numbers";
    return false;
  }
  return true;
}

void GradientEstimator::RestoreExtra(const EstimatorState& state) {
  // What a state does not carry starts empty: no statistics, no previous direction.
  const int F = layout_.num_features(), n = layout_.num_parameters();
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
  if (state.directions.size() > 0) {
    previous_g_ = state.directions.head(F);
    previous_dw_ = state.directions.segment(F, F);
    previous_dx_ = state.directions.segment(2 * F, n);
    previous_zg_ = state.directions[2 * F + n];
    has_previous_ = state.directions[2 * F + n + 1] != 0.0;
  }
}

}  // namespace inertial
