#include "inertial/estimation/online/online_fit.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "inertial/estimation/fit_uncertainty.hpp"
#include "inertial/estimation/batch/robust_identification.hpp"
#include "inertial/signal/robust_statistics.hpp"
#include "inertial/estimation/online/symmetric_rank_update.hpp"
#include "inertial/estimation/online/symmetric_span_product.hpp"

namespace inertial {
namespace {

int RoundUpToBlock(int k) { return (k + kSpanBlock - 1) / kSpanBlock * kSpanBlock; }

// Per joint the robust scale s_j = 1.4826 median |r_j| of the prediction errors r (m x count):
// about zero, not about their median, because the errors are those of earlier estimates, whose
// bias the current one need not share (a bias of them is spread, not a centre). Floored as
// identify floors its scale (robust_identification.hpp): 1e-3 of the RMS of the joint's measured
// torque y, and 1e-9.
void RobustNoise(const Eigen::MatrixXd& r, const Eigen::MatrixXd& y, Eigen::VectorXd* center, Eigen::VectorXd* scale) {
  const int m = static_cast<int>(r.rows()), n = static_cast<int>(r.cols());
  center->setZero(m);
  scale->setZero(m);
  std::vector<double> v(n);
  for (int j = 0; j < m; ++j) {
    for (int i = 0; i < n; ++i) v[i] = std::abs(r(j, i));
    const double rms = std::sqrt(y.row(j).squaredNorm() / n);
    (*scale)[j] = std::max({kMadToSigma * Median(v), 1e-3 * rms, 1e-9});
  }
}

bool WithinGate(const Eigen::VectorXd& r, const Eigen::VectorXd& center, const Eigen::VectorXd& scale, double k) {
  for (int j = 0; j < r.size(); ++j) {
    if (!(std::abs(r[j] - center[j]) <= k * scale[j])) return false;
  }
  return true;
}

// The covariance of the coefficients w at the solution, C_w = J_w C_x J_w^T with C_x the Laplace
// covariance of the batch objective (fit_uncertainty.hpp): a^T C_w a is the variance of the
// prediction a^T w that the estimate's own uncertainty adds to the noise. Directions nothing
// determines (infinite variance) get 1e200 on the diagonal: a gate open for the samples that
// excite them, since nothing can be judged there.
Eigen::MatrixXd PredictionCovariance(const RobotDynamics& model, const FitUncertainty* u, const Eigen::VectorXd& x) {
  const int F = model.num_features(), P = model.num_parameters();
  constexpr double kOpen = 1e200;
  if (u == nullptr) return Eigen::MatrixXd::Identity(F, F) * kOpen;  // no residual degrees of freedom yet
  Eigen::MatrixXd C_x = u->covariance;
  for (int i = 0; i < P; ++i) {
    for (int j = 0; j < P; ++j) {
      if (!std::isfinite(C_x(i, j))) C_x(i, j) = i == j ? kOpen : 0.0;
    }
  }
  Eigen::MatrixXd J;
  model.Coefficients(x, &J);
  Eigen::MatrixXd C_w = J * C_x * J.transpose();
  for (int f = 0; f < F; ++f) {
    if (!std::isfinite(C_w(f, f)) || C_w(f, f) > kOpen) C_w(f, f) = kOpen;
  }
  return C_w.unaryExpr([](double v) { return std::isfinite(v) ? v : 0.0; });
}

}  // namespace

namespace {

void AddRows(const Eigen::Ref<const Eigen::MatrixXd>& At, const Eigen::Ref<const Eigen::VectorXd>& y,
             JointNormalEquations* eq) {
  eq->AtA.noalias() += At * At.transpose();
  eq->Atb.noalias() += At * y;
  eq->btb += y.squaredNorm();
  ++eq->num_samples;
}

// The blocks as EstimateFitUncertainty takes them: none if fewer than kMinTimeBlocks (too noisy a
// spread: fit_uncertainty.hpp); the length reported is their mean; no correlation time (none is
// measured online).
TimeBlocks UsableBlocks(std::vector<JointNormalEquations> blocks) {
  TimeBlocks tb;
  if (static_cast<int>(blocks.size()) < kMinTimeBlocks) return tb;
  double samples = 0.0;
  for (const JointNormalEquations& b : blocks) samples += b.num_samples;
  tb.block_length = static_cast<int>(std::lround(samples / static_cast<double>(blocks.size())));
  tb.pieces = 1;
  tb.blocks = std::move(blocks);
  return tb;
}

// Block statistics as JointNormalEquations: the lower triangle mirrored.
JointNormalEquations BlockEquations(const Eigen::MatrixXd& lower, const Eigen::VectorXd& s, double c, double n) {
  JointNormalEquations b;
  b.AtA = lower.selfadjointView<Eigen::Lower>();
  b.Atb = s;
  b.btb = c;
  b.num_samples = static_cast<int>(std::min(std::round(n), 2147483647.0));
  return b;
}

}  // namespace

OnlineFitSolution SolveOnlineFit(const RobotDynamics& model, const OnlineFitSnapshot& snap,
                                 const OnlineFitOptions& options) {
  OnlineFitSolution sol;
  sol.generation = snap.generation;
  const int m = model.num_dofs();
  const int count = static_cast<int>(snap.pending_y.cols());
  const long long judged = std::max<long long>(1, snap.residuals_seen);
  sol.gate = options.gate > 0 ? options.gate : DefaultOutlierThreshold(judged);
  if (snap.window_r.cols() > 0) RobustNoise(snap.window_r, snap.window_y, &sol.center, &sol.noise);
  sol.pending_kept.assign(count, true);
  JointIdentificationOptions fit = options.solve;
  fit.initial = snap.solved ? snap.x : Eigen::VectorXd();
  // The pending samples (the warm-up, or samples the gate refused since the last solve) are
  // judged as identify judges rows: the fit with them, then each against that fit's prediction
  // (a fit that has seen a velocity reversal or a new region of the workspace explains it; a
  // glitch stays far out), and the fit again without those refused.
  auto fit_with = [&](const std::vector<bool>& kept) {
    JointNormalEquations eq = snap.equations;
    for (int i = 0; i < count; ++i) {
      if (kept[i]) AddRows(snap.pending_rows.middleCols(i * m, m), snap.pending_y.col(i), &eq);
    }
    return eq;
  };
  auto judge = [&](const Eigen::VectorXd& x, std::vector<bool>* kept) {
    const Eigen::VectorXd w = model.Coefficients(x);
    for (int i = 0; i < count; ++i) {
      const Eigen::VectorXd r = snap.pending_y.col(i) - snap.pending_rows.middleCols(i * m, m).transpose() * w;
      (*kept)[i] = WithinGate(r, sol.center, sol.noise, sol.gate);
    }
  };
  const bool can_judge = count > 0 && sol.noise.size() == m;
  // The warm-up is first judged against the start (identify's first round, against the prior);
  // samples the gate held are first taken in (their fit must see them to judge them).
  if (can_judge && !snap.solved) judge(snap.x, &sol.pending_kept);
  JointNormalEquations eq = fit_with(sol.pending_kept);
  if (eq.num_samples == 0) {
    sol.x = snap.x;
    return sol;
  }
  JointIdentificationResult result = IdentifyJointModel(model, eq, fit);
  // Re-judged against each fit until the kept set settles (at most identify's 5 rounds).
  for (int round = 1; can_judge && round < 5; ++round) {
    std::vector<bool> kept(count);
    judge(result.x, &kept);
    if (kept == sol.pending_kept) break;
    sol.pending_kept = kept;
    eq = fit_with(kept);
    if (eq.num_samples == 0) break;
    fit.initial = result.x;
    result = IdentifyJointModel(model, eq, fit);
  }
  sol.x = result.x;
  sol.lm = result.lm;
  // The time blocks (online_fit.hpp): the held samples kept joined the statistics now, so the
  // open (last) block's.
  TimeBlocks blocks;
  if (!snap.blocks.empty()) {
    blocks.blocks = snap.blocks;
    for (int i = 0; i < count; ++i) {
      if (sol.pending_kept[i]) AddRows(snap.pending_rows.middleCols(i * m, m), snap.pending_y.col(i), &blocks.blocks.back());
    }
  }
  blocks = UsableBlocks(std::move(blocks.blocks));
  try {
    sol.uncertainty = std::make_shared<const FitUncertainty>(
        EstimateFitUncertainty(model, eq, sol.x, fit.prior_weight, fit.frozen_bodies, blocks));
  } catch (const std::invalid_argument&) {  // no residual degrees of freedom yet
  }
  sol.prediction_covariance = PredictionCovariance(model, sol.uncertainty.get(), sol.x);
  return sol;
}

OnlineFit::OnlineFit(RobotDynamics model, const Eigen::VectorXd& x0, const OnlineFitOptions& options)
    : RecursiveEstimator(model.num_features(), model.num_dofs()), model_(std::move(model)), options_(options) {
  m_ = model_.num_dofs();
  F_ = model_.num_features();
  Fp_ = RoundUpToBlock(F_);
  if (x0.size() != model_.num_parameters() || !x0.allFinite()) {
    throw std::invalid_argument("online fit: x0 must be " + std::to_string(model_.num_parameters()) + " finite numbers");
  }
  if (!(options.solve.prior_weight >= 0) || !std::isfinite(options.solve.prior_weight)) {
    throw std::invalid_argument("online fit: the prior weight must be finite and non-negative");
  }
  if (!(options.forgetting_time > 0)) throw std::invalid_argument("online fit: the forgetting time must be positive");
  if (!(options.gate >= 0) || !std::isfinite(options.gate)) throw std::invalid_argument("online fit: the gate must be >= 0");
  if (options.noise_window < 8 || options.warmup < 1 || options.max_consecutive_outliers < 1 ||
      !(options.solve_growth > 0)) {
    throw std::invalid_argument(
        "online fit: noise_window >= 8, warmup >= 1, max_consecutive_outliers >= 1 and solve_growth > 0 required");
  }
  if (!options.solve.frozen_bodies.empty() && options.solve.frozen_bodies.size() != model_.bodies().size()) {
    throw std::invalid_argument("online fit: frozen_bodies must have one flag per estimated body");
  }
  x_ = x0;
  w_ = model_.Coefficients(x_);
  S_ = Eigen::MatrixXd::Zero(Fp_, Fp_);
  s_ = Eigen::VectorXd::Zero(F_);
  At_ = Eigen::MatrixXd::Zero(Fp_, RoundUpToBlock(m_));
  CwAt_ = Eigen::MatrixXd::Zero(Fp_, RoundUpToBlock(m_));
  Ar_ = Eigen::MatrixXd::Zero(F_, m_);
  ys_ = Eigen::VectorXd::Zero(m_);
  order_.assign(static_cast<size_t>(m_), 0);
  first_.assign(static_cast<size_t>(m_), 0);
  end_.assign(static_cast<size_t>(m_), 0);
  Cw_ = Eigen::MatrixXd::Zero(Fp_, Fp_);
  gate_scale_ = Eigen::VectorXd::Zero(m_);
  ones_ = Eigen::VectorXd::Ones(Fp_);
  d_ = Eigen::VectorXd::Ones(Fp_);
  r_ = Eigen::VectorXd::Zero(m_);
  capacity_ = std::max(options.warmup, options.max_consecutive_outliers);
  pending_rows_ = Eigen::MatrixXd::Zero(F_, static_cast<Eigen::Index>(m_) * capacity_);
  pending_y_ = Eigen::MatrixXd::Zero(m_, capacity_);
  pending_place_.assign(static_cast<size_t>(capacity_), 0);
  pending_run_.assign(static_cast<size_t>(capacity_), 0);
  if (!std::isfinite(options.forgetting_time)) {  // time blocks (header): preallocated, none with forgetting
    ends_S_.assign(kMaxTimeBlocks + 1, Eigen::MatrixXd::Zero(F_, F_));
    ends_s_.assign(kMaxTimeBlocks + 1, Eigen::VectorXd::Zero(F_));
    ends_c_.assign(kMaxTimeBlocks + 1, 0.0);
    ends_n_.assign(kMaxTimeBlocks + 1, 0.0);
  }
  window_r_ = Eigen::MatrixXd::Zero(m_, options.noise_window);
  window_y_ = Eigen::MatrixXd::Zero(m_, options.noise_window);
  noise_ = Eigen::VectorXd::Zero(m_);
  center_ = Eigen::VectorXd::Zero(m_);
}

void OnlineFit::LoadRows(const Eigen::Ref<const Eigen::MatrixXd>& rows_t) {
  for (int j = 0; j < m_; ++j) {  // insertion sort by first (m is a robot's joints: no allocation)
    int c = 0, e = 0;
    NonzeroSpan(rows_t.col(j), &c, &e);
    if (c == e) c = e = Fp_;
    int k = j;
    for (; k > 0 && first_[static_cast<size_t>(k - 1)] > c; --k) {
      first_[static_cast<size_t>(k)] = first_[static_cast<size_t>(k - 1)];
      end_[static_cast<size_t>(k)] = end_[static_cast<size_t>(k - 1)];
      order_[static_cast<size_t>(k)] = order_[static_cast<size_t>(k - 1)];
    }
    first_[static_cast<size_t>(k)] = c;
    end_[static_cast<size_t>(k)] = e;
    order_[static_cast<size_t>(k)] = j;
  }
  for (int k = 0; k < m_; ++k) At_.col(k).head(F_) = rows_t.col(order_[static_cast<size_t>(k)]);
}

void OnlineFit::AddAtToS() {
  // One pass over S in which each column block takes only the rows that have begun there: for a
  // serial chain about a third of the F^2 m / 2 multiply-adds of the plain rank update.
  SymmetricSpanRankUpdate(S_, At_.leftCols(m_), first_.data(), ones_, -1.0);
}

void OnlineFit::Accumulate(const Eigen::VectorXd& y, double lambda) {
  for (int k = 0; k < m_; ++k) ys_[k] = y[order_[static_cast<size_t>(k)]];
  if (lambda == 1.0) {
    AddAtToS();
  } else {
    d_.setConstant(std::sqrt(lambda));
    ScaledSymmetricRankUpdate(S_, d_, At_.leftCols(m_), -1.0);
  }
  s_ = lambda * s_;
  s_.noalias() += At_.topLeftCorner(F_, m_) * ys_;
  c_ = lambda * c_ + y.squaredNorm();
  weight_ = lambda * weight_ + 1.0;
  added_since_solve_ = lambda * added_since_solve_ + 1.0;
  EndBlockIfDue();
}

void OnlineFit::EndBlockIfDue() {
  if (ends_S_.empty()) return;
  const double open = weight_ - ends_n_[ends_];
  if (!(open >= std::max(kMinBlockSamples, (weight_ - ends_n_[0]) / kTargetTimeBlocks))) return;
  if (ends_ == kMaxTimeBlocks) {
    // The neighbours with the fewest samples together become one: their common end is dropped
    // (the later ends move down by swapping, no copy), so the blocks stay near-equal and in order.
    int drop = 1;
    for (int k = 2; k < ends_; ++k) {
      if (ends_n_[k + 1] - ends_n_[k - 1] < ends_n_[drop + 1] - ends_n_[drop - 1]) drop = k;
    }
    for (int k = drop; k < ends_; ++k) {
      ends_S_[k].swap(ends_S_[k + 1]);
      ends_s_[k].swap(ends_s_[k + 1]);
      std::swap(ends_c_[k], ends_c_[k + 1]);
      std::swap(ends_n_[k], ends_n_[k + 1]);
    }
    --ends_;
  }
  // The sums at the new end: the only F x F pass of a block's end.
  ++ends_;
  ends_S_[ends_] = S_.topLeftCorner(F_, F_);
  ends_s_[ends_] = s_;
  ends_c_[ends_] = c_;
  ends_n_[ends_] = weight_;
}

void OnlineFit::ResetBlocks() {
  ends_ = 0;
  if (ends_S_.empty()) return;
  ends_S_[0] = S_.topLeftCorner(F_, F_);  // the sums the blocks start from (zero, or restored)
  ends_s_[0] = s_;
  ends_c_[0] = c_;
  ends_n_[0] = weight_;
}

std::vector<JointNormalEquations> OnlineFit::Blocks() const {
  std::vector<JointNormalEquations> blocks;
  if (ends_S_.empty()) return blocks;
  blocks.reserve(ends_ + 1);
  for (int k = 1; k <= ends_; ++k) {
    const Eigen::MatrixXd d = ends_S_[k] - ends_S_[k - 1];
    blocks.push_back(BlockEquations(d, ends_s_[k] - ends_s_[k - 1], ends_c_[k] - ends_c_[k - 1],
                                    ends_n_[k] - ends_n_[k - 1]));
  }
  if (weight_ - ends_n_[ends_] > 0.0) {
    const Eigen::MatrixXd open = S_.topLeftCorner(F_, F_) - ends_S_[ends_];
    blocks.push_back(BlockEquations(open, s_ - ends_s_[ends_], c_ - ends_c_[ends_], weight_ - ends_n_[ends_]));
  }
  return blocks;
}

UpdateStatus OnlineFit::Apply(const Eigen::MatrixXd& A, const Eigen::VectorXd& y) {
  r_ = y;
  r_.noalias() -= A * w_;
  if (!r_.allFinite()) return UpdateStatus::kNumerical;
  // The window of prediction errors (every finite sample: the noise is judged on all of them).
  window_r_.col(window_next_) = r_;
  window_y_.col(window_next_) = y;
  window_next_ = (window_next_ + 1) % options_.noise_window;
  window_count_ = std::min(window_count_ + 1, options_.noise_window);
  residuals_seen_ += m_;
  const double lambda =
      (has_time() && std::isfinite(options_.forgetting_time)) ? std::exp(-(applying_time() - last_time()) / options_.forgetting_time) : 1.0;
  if (!has_scale_ && pending_count_ < capacity_) {
    Hold(A, y);
    return UpdateStatus::kBuffered;
  }
  Ar_ = A.transpose();
  LoadRows(Ar_);
  if (!has_scale_) {  // the caller has not solved since the warm-up filled: nothing to judge by yet
    Accumulate(y, lambda);
    return UpdateStatus::kAccepted;
  }
  // The gate: noise plus what the estimate's uncertainty adds to this sample's prediction
  // (a_j^T C_w a_j: large where the samples so far did not excite what this one does).
  // A's rows sorted by where they begin (LoadRows), four at a time: each group's quadratic forms
  // over the diagonal block of its span alone, (e - c)^2 per group instead of F^2
  // (symmetric_span_product.hpp).
  for (int g0 = 0; g0 < m_; g0 += kSpanBlock) {
    const int g1 = std::min(g0 + kSpanBlock, m_);
    int c = Fp_, e = 0;
    for (int k = g0; k < g1; ++k) {
      if (first_[static_cast<size_t>(k)] < end_[static_cast<size_t>(k)]) {
        c = std::min(c, first_[static_cast<size_t>(k)]);
        e = std::max(e, end_[static_cast<size_t>(k)]);
      }
    }
    c = c / kSpanBlock * kSpanBlock;
    const int len = c < e ? RoundUpToBlock(e) - c : 0;
    if (len > 0) {
      SymmetricSpanProduct(Cw_.block(c, c, len, len), At_.block(c, g0, len, kSpanBlock), 0, len,
                           CwAt_.block(c, g0, len, kSpanBlock));
    }
    for (int k = g0; k < g1; ++k) {
      const double q = len > 0 ? At_.col(k).segment(c, len).dot(CwAt_.col(k).segment(c, len)) : 0.0;
      gate_scale_[order_[static_cast<size_t>(k)]] = std::sqrt(noise_[order_[static_cast<size_t>(k)]] * noise_[order_[static_cast<size_t>(k)]] + std::max(0.0, q));
    }
  }
  if (!WithinGate(r_, center_, gate_scale_, gate_)) {
    // Held for the next solve, which judges it with the fit that includes it; a run longer than
    // max_consecutive_outliers, which a solve has judged and still refused, is a change of the
    // system: start over from the current estimate. A run no solve has judged yet is only a gate
    // that has fallen behind (a solver thread slowed by a loaded machine, its estimate many samples
    // old): the statistics are kept, and what finds no room to wait is refused.
    if (consecutive_ == 0) ++run_id_;
    if (++consecutive_ <= options_.max_consecutive_outliers || !run_judged_) {
      if (pending_count_ >= capacity_) return UpdateStatus::kOutlier;  // no room left before the next solve
      Hold(A, y, consecutive_);
      return UpdateStatus::kBuffered;
    }
    ++changes_;
    for (int i = 0; i < pending_count_; ++i) ResolveHeld(false);  // the run before the change
    Empty();
    Hold(A, y);
    return UpdateStatus::kBuffered;
  }
  consecutive_ = 0;
  run_judged_ = false;
  Accumulate(y, lambda);
  return UpdateStatus::kAccepted;
}

void OnlineFit::Hold(const Eigen::MatrixXd& A, const Eigen::VectorXd& y, int place) {
  pending_rows_.middleCols(static_cast<Eigen::Index>(pending_count_) * m_, m_) = A.transpose();
  pending_y_.col(pending_count_) = y;
  pending_place_[static_cast<size_t>(pending_count_)] = place;
  pending_run_[static_cast<size_t>(pending_count_)] = run_id_;
  ++pending_count_;
}

void OnlineFit::ResolveHeld(bool kept) {
  Resolve(kept ? UpdateStatus::kAccepted : UpdateStatus::kOutlier);
  ++(kept ? held_kept_ : held_refused_);
}

void OnlineFit::Empty() {
  S_.setZero();
  s_.setZero();
  c_ = 0.0;
  weight_ = 0.0;
  pending_count_ = 0;
  has_scale_ = false;
  consecutive_ = 0;
  run_judged_ = false;
  added_since_solve_ = 0.0;
  ResetBlocks();
  ++generation_;
}

bool OnlineFit::solve_due() const {
  if (!has_scale_) return pending_count_ >= options_.warmup;
  // Refused samples wait for a solve to judge them: soon, but not at every one of a run.
  if (pending_count_ >= kPendingSolve) return true;
  // Grown by the fraction g since the last solve: the weight added since, decayed as the rest,
  // is g / (1 + g) of the whole (without forgetting: weight >= (1 + g) weight at the solve; with
  // it, the same rule stays reachable once the weight saturates at 1 / (1 - lambda)).
  const double g = options_.solve_growth;
  return added_since_solve_ > 0.0 && added_since_solve_ >= g / (1.0 + g) * weight_;
}

JointNormalEquations OnlineFit::Equations() const {
  JointNormalEquations eq;
  eq.AtA = S_.topLeftCorner(F_, F_);
  eq.AtA.triangularView<Eigen::StrictlyUpper>() = eq.AtA.transpose();
  eq.Atb = s_;
  eq.btb = c_;
  // The count saturates at 2^31 - 1 samples (25 days at 1 kHz without forgetting); beyond, the
  // Laplace covariance's noise estimate counts fewer rows than it has (it grows, conservative).
  eq.num_samples = static_cast<int>(std::min(std::round(weight_), 2147483647.0));
  return eq;
}

OnlineFitSnapshot OnlineFit::Snapshot() const {
  OnlineFitSnapshot snap;
  snap.equations = Equations();
  snap.x = x_;
  snap.solved = solved_;
  snap.pending_rows = pending_rows_.leftCols(static_cast<Eigen::Index>(pending_count_) * m_);
  snap.pending_y = pending_y_.leftCols(pending_count_);
  snap.window_r.resize(m_, window_count_);
  snap.window_y.resize(m_, window_count_);
  for (int i = 0; i < window_count_; ++i) {
    snap.window_r.col(i) = window_r_.col(i);
    snap.window_y.col(i) = window_y_.col(i);
  }
  snap.residuals_seen = residuals_seen_;
  snap.generation = generation_;
  snap.blocks = Blocks();
  return snap;
}

bool OnlineFit::Adopt(const OnlineFitSolution& sol) {
  // An estimate that is not finite or beyond any physical scale is not taken (the last one stays);
  // the noise, the gate and the held samples' judgement are taken all the same, so that a failed
  // solve does not leave the solve due at every sample.
  bool take_x = sol.x.size() == x_.size() && sol.x.allFinite();
  Eigen::VectorXd w;
  if (take_x) {
    w = model_.Coefficients(sol.x);
    take_x = w.allFinite() && w.cwiseAbs().maxCoeff() <= kMaxStateCoefficient;
  }
  if (take_x) {
    x_ = sol.x;
    w_ = w;
    uncertainty_ = sol.uncertainty;
  }
  if (sol.generation != generation_) return take_x;  // the statistics were emptied meanwhile
  if (sol.noise.size() == m_) {
    // The held samples the solve kept join the statistics (at their weight now: they are
    // recent); those it refused are counted as outliers; those held after the snapshot stay.
    const int judged = std::min(static_cast<int>(sol.pending_kept.size()), pending_count_);
    // The current run of refusals (places 1, 2, ... in it): the samples up to the last one of it the
    // solve kept no longer count; the rest of the run is judged only if the solve refused one of it
    // after that (a refusal of an earlier run, or before a kept sample, judges nothing of it).
    const auto in_run = [&](int i) {
      return consecutive_ > 0 && pending_place_[static_cast<size_t>(i)] > 0 && pending_run_[static_cast<size_t>(i)] == run_id_;
    };
    int last_kept = 0;
    bool run_seen = false;
    for (int i = 0; i < judged; ++i) {
      if (!in_run(i)) continue;
      run_seen = true;
      if (sol.pending_kept[i]) last_kept = std::max(last_kept, pending_place_[static_cast<size_t>(i)]);
    }
    bool refused_after = false;
    for (int i = 0; i < judged; ++i) {
      refused_after = refused_after || (in_run(i) && !sol.pending_kept[i] && pending_place_[static_cast<size_t>(i)] > last_kept);
    }
    if (run_seen) {
      consecutive_ -= last_kept;
      run_judged_ = (last_kept > 0 ? false : run_judged_) || refused_after;
      if (consecutive_ == 0) run_judged_ = false;
    }
    for (int i = 0; i < judged; ++i) {
      ResolveHeld(sol.pending_kept[i]);
      if (!sol.pending_kept[i]) continue;
      LoadRows(pending_rows_.middleCols(static_cast<Eigen::Index>(i) * m_, m_));
      AddAtToS();
      s_.noalias() += pending_rows_.middleCols(static_cast<Eigen::Index>(i) * m_, m_) * pending_y_.col(i);
      c_ += pending_y_.col(i).squaredNorm();
      weight_ += 1.0;
    }
    const int rest = pending_count_ - judged;
    if (rest > 0) {
      pending_rows_.leftCols(static_cast<Eigen::Index>(rest) * m_) =
          pending_rows_.middleCols(static_cast<Eigen::Index>(judged) * m_, static_cast<Eigen::Index>(rest) * m_).eval();
      pending_y_.leftCols(rest) = pending_y_.middleCols(judged, rest).eval();
    }
    for (int i = 0; i < rest; ++i) {  // their places in the run, counted from its new start
      const size_t from = static_cast<size_t>(judged + i), to = static_cast<size_t>(i);
      const bool same_run = pending_place_[from] > 0 && pending_run_[from] == run_id_;
      pending_place_[to] = same_run ? pending_place_[from] - last_kept : pending_place_[from];
      pending_run_[to] = pending_run_[from];
    }
    pending_count_ = rest;
    EndBlockIfDue();
  }
  if (sol.prediction_covariance.rows() == F_ && sol.prediction_covariance.cols() == F_) {
    Cw_.topLeftCorner(F_, F_) = sol.prediction_covariance;
  }
  if (sol.noise.size() == m_) {
    noise_ = sol.noise;
    center_ = sol.center;
    gate_ = sol.gate;
    has_scale_ = true;
  }
  solved_ = solved_ || (take_x && sol.lm.x.size() > 0);
  added_since_solve_ = 0.0;
  ++solves_;
  return take_x;
}

bool OnlineFit::Solve(bool from_start) {
  OnlineFitSnapshot snap = Snapshot();
  if (from_start) snap.solved = false;
  if (snap.equations.num_samples == 0 && snap.pending_y.cols() == 0) return false;
  return Adopt(SolveOnlineFit(model_, snap, options_));
}

Eigen::MatrixXd OnlineFit::Covariance() const {
  const JointNormalEquations eq = Equations();
  if (static_cast<double>(eq.num_samples) * m_ <= model_.num_parameters()) return {};
  try {
    return EstimateFitUncertainty(model_, eq, x_, options_.solve.prior_weight, options_.solve.frozen_bodies,
                                  UsableBlocks(Blocks()))
        .covariance;
  } catch (const std::invalid_argument&) {
    return {};  // no residual degrees of freedom yet
  }
}

Eigen::MatrixXd OnlineFit::StatisticsMatrix() const {
  Eigen::MatrixXd M(F_ + 1, F_ + 1);
  const JointNormalEquations eq = Equations();
  M.topLeftCorner(F_, F_) = eq.AtA;
  M.col(F_).head(F_) = eq.Atb;
  M.row(F_).head(F_) = eq.Atb.transpose();
  M(F_, F_) = eq.btb;
  return M;
}

bool OnlineFit::CheckExtra(const EstimatorState& state, std::string* why) const {
  const Eigen::MatrixXd& M = state.statistics;
  if (M.size() == 0) {
    if (why != nullptr) *why = "the state holds no statistics (written by another estimator or an older version)";
    return false;
  }
  if (M.rows() != F_ + 1 || M.cols() != F_ + 1) {
    if (why != nullptr) {
      *why = "its statistics are " + std::to_string(M.rows()) + " x " + std::to_string(M.cols()) + ", the model needs " +
             std::to_string(F_ + 1) + " x " + std::to_string(F_ + 1);
    }
    return false;
  }
  if (!M.allFinite() || !std::isfinite(state.statistics_samples) || state.statistics_samples < 0) {
    if (why != nullptr) *why = "its statistics hold non-finite or negative numbers";
    return false;
  }
  // 1e12 samples: 30 years at 1 kHz; more is not a count any stream could have made.
  if (!(state.statistics_samples <= 1e12)) {
    if (why != nullptr) *why = "its statistics claim more than 1e12 samples";
    return false;
  }
  const double scale = M.cwiseAbs().maxCoeff();
  if (!((M - M.transpose()).cwiseAbs().maxCoeff() <= 1e-9 * scale) || (M.diagonal().array() < 0).any()) {
    if (why != nullptr) *why = "its statistics are not a symmetric matrix with a non-negative diagonal";
    return false;
  }
  return true;
}

void OnlineFit::SaveExtra(EstimatorState* state) const {
  // The held samples go into the saved statistics as accepted (a checkpoint must not lose them;
  // the gate's judgement of them is the one thing a restart forgoes).
  state->statistics = StatisticsMatrix();
  state->statistics_samples = weight_;
  for (int i = 0; i < pending_count_; ++i) {
    Eigen::VectorXd v(F_ + 1);
    v.head(F_).setZero();
    for (int j = 0; j < m_; ++j) {
      v.head(F_) = pending_rows_.col(static_cast<Eigen::Index>(i) * m_ + j);
      v[F_] = pending_y_(j, i);
      state->statistics.selfadjointView<Eigen::Lower>().rankUpdate(v);
    }
    state->statistics_samples += 1.0;
    auto& count = state->counters.count;  // a held sample is counted buffered until resolved
    ++count[static_cast<int>(UpdateStatus::kAccepted)];
    if (count[static_cast<int>(UpdateStatus::kBuffered)] > 0) --count[static_cast<int>(UpdateStatus::kBuffered)];
  }
  state->statistics.triangularView<Eigen::StrictlyUpper>() = state->statistics.transpose();
  state->solved = solved_;
}

void OnlineFit::RestoreExtra(const EstimatorState& state) {
  const Eigen::MatrixXd& M = state.statistics;
  S_.setZero();
  S_.topLeftCorner(F_, F_) = M.topLeftCorner(F_, F_);
  s_ = M.col(F_).head(F_);
  c_ = M(F_, F_);
  weight_ = state.statistics_samples;
  // A restored estimate (x not the priors: a checkpoint, or one carried into a model with more
  // effects, whose statistics start over) is the warm start of the next solve.
  solved_ = state.solved || !state.x.isZero(0.0);
  // The gate is found again from the next samples (a warm-up): the noise may have changed.
  added_since_solve_ = 0.0;
  pending_count_ = 0;
  window_count_ = 0;
  window_next_ = 0;
  has_scale_ = false;
  consecutive_ = 0;
  run_judged_ = false;
  // The checkpoint keeps the sums, not the blocks: blocks of the samples from here on.
  ResetBlocks();
  ++generation_;
}

bool OnlineFit::SetParameters(const Eigen::VectorXd& x, const Eigen::MatrixXd&, std::string*) {
  x_ = x;
  w_ = model_.Coefficients(x_);
  return true;
}

}  // namespace inertial
