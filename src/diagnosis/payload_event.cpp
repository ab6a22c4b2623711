#include "inertial/diagnosis/payload_event.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

#include "inertial/estimation/fit_uncertainty.hpp"
#include "inertial/model/body_region.hpp"
#include "inertial/model/number_text.hpp"

namespace inertial {

namespace {

void Require(bool ok, const char* what, double value) {
  if (!ok) {
    throw std::invalid_argument(std::string("PayloadEventDetector: ") + what + " (got " + FormatNumber(value, 6) + ")");
  }
}

int Blocks(double time, double block) { return static_cast<int>(std::lround(time / block)); }

// (N + eps I)^-1 with eps 1e-6 of N's mean eigenvalue: directions the span excites less than that
// (N's null space, where g has no component either, and directions a million times weaker than
// the typical one, where a fit would amplify model error rather than measure a body) are left
// out; the rest is N^-1.
constexpr double kRidge = 1e-6;
Matrix10 RegularizedInverse(const Matrix10& N) {
  const double eps = kRidge * (N.trace() / 10.0) + 1e-300;
  const Eigen::LLT<Matrix10> llt(N + eps * Matrix10::Identity());
  return llt.solve(Matrix10::Identity());
}

// g^T (N + eps I)^-1 g and the solution, by one Cholesky factorization.
double Explained(const Matrix10& N, const Vector10& g, Vector10* d = nullptr) {
  const double eps = kRidge * (N.trace() / 10.0) + 1e-300;
  const Eigen::LLT<Matrix10> llt(N + eps * Matrix10::Identity());
  const Vector10 x = llt.solve(g);
  if (d != nullptr) *d = x;
  const double e = g.dot(x);
  return std::isfinite(e) ? std::max(0.0, e) : 0.0;
}

}  // namespace

double ChiSquareTailEven(int k, double x) {
  if (x <= 0) return 1.0;
  const double h = 0.5 * x;
  double term = 1.0, sum = 1.0;
  for (int i = 1; i < k / 2; ++i) {
    term *= h / i;
    sum += term;
  }
  return std::exp(-h) * sum;
}

double ChiSquareQuantileEven(int k, double p) {
  double lo = 0.0, hi = 10.0;
  while (ChiSquareTailEven(k, hi) > p) hi *= 2.0;
  for (int i = 0; i < 200 && hi - lo > 1e-12 * hi; ++i) {
    const double mid = 0.5 * (lo + hi);
    (ChiSquareTailEven(k, mid) > p ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

std::string PayloadEventText(const PayloadEvent& e) {
  char buf[400];
  std::snprintf(buf, sizeof buf,
                "t = %.2f s: payload %s on %s: %+.3f +- %.3f kg at COM (%.3f, %.3f, %.3f) +- (%.3f, %.3f, %.3f) m "
                "(onset %.2f s, %s %.2f s)",
                e.detection_time, e.added_mass >= 0 ? "picked up" : "put down", e.link.c_str(), e.added_mass,
                e.added_mass_std, e.com[0], e.com[1], e.com[2], e.com_std[0], e.com_std[1], e.com_std[2], e.onset_time,
                e.settled ? "settled at" : "not settled at", e.settle_time);
  return buf;
}

PayloadEventDetector::PayloadEventDetector(const OnlineJointEstimator& estimator, const PayloadEventOptions& options)
    : options_(options) {
  const PayloadEventOptions& o = options;
  Require(std::isfinite(o.block_time) && o.block_time > 0, "block_time must be finite and positive", o.block_time);
  Require(std::isfinite(o.max_window) && o.max_window >= o.block_time, "max_window must be finite and >= block_time",
          o.max_window);
  Require(std::isfinite(o.min_reference_time) && o.min_reference_time >= o.block_time,
          "min_reference_time must be finite and >= block_time", o.min_reference_time);
  Require(std::isfinite(o.reference_time) && o.reference_time >= o.min_reference_time,
          "reference_time must be finite and >= min_reference_time", o.reference_time);
  Require(std::isfinite(o.calibration_time) && o.calibration_time >= o.block_time,
          "calibration_time must be finite and >= block_time", o.calibration_time);
  Require(std::isfinite(o.arm_time) && o.arm_time >= 0, "arm_time must be finite and >= 0", o.arm_time);
  Require(o.false_alarm_rate > 0 && o.false_alarm_rate <= 1e6, "false_alarm_rate must be in (0, 1e6] per hour",
          o.false_alarm_rate);
  Require(std::isfinite(o.confirm_time) && o.confirm_time >= o.block_time, "confirm_time must be finite and >= block_time",
          o.confirm_time);
  Require(o.mass_std_fraction > 0 && o.mass_std_fraction <= 1, "mass_std_fraction must be in (0, 1]",
          o.mass_std_fraction);
  Require(std::isfinite(o.max_settle_time) && o.max_settle_time >= 0, "max_settle_time must be finite and >= 0",
          o.max_settle_time);
  Require(std::isfinite(o.min_settle_time) && o.min_settle_time >= 0, "min_settle_time must be finite and >= 0",
          o.min_settle_time);
  // At most 1e5 blocks in the ring (e.g. 10 s of reference in 0.1 ms blocks).
  Require((o.reference_time + o.max_window + o.confirm_time + o.max_settle_time + o.min_settle_time) / o.block_time <= 1e5,
          "block_time too short for the spans it must hold (at most 1e5 blocks)", o.block_time);

  const RobotDynamics& model = estimator.model();
  m_ = model.num_dofs();
  for (int e = 0; e < static_cast<int>(model.bodies().size()); ++e) {
    const EstimatedBody& b = model.bodies()[e];
    if (b.name.rfind("rotor@", 0) == 0) continue;  // a payload sits on a link, not on a motor's rotor
    const int block = b.tree_body;  // a payload effect on a link: the link's columns, reported as the link
    if (std::find(candidates_block_.begin(), candidates_block_.end(), block) != candidates_block_.end()) continue;
    candidates_block_.push_back(block);
    candidates_body_.push_back(e);
  }
  window_blocks_ = std::max(1, Blocks(o.max_window, o.block_time));
  reference_blocks_ = std::max(1, Blocks(o.reference_time, o.block_time));
  min_reference_blocks_ = std::max(1, Blocks(o.min_reference_time, o.block_time));
  calibration_blocks_ = std::max(1, Blocks(o.calibration_time, o.block_time));
  onsets_ = window_blocks_;
  const int ring = reference_blocks_ + window_blocks_ + static_cast<int>(std::ceil(o.confirm_time / o.block_time)) +
                   static_cast<int>(std::ceil((o.max_settle_time + o.min_settle_time) / o.block_time)) +
                   calibration_blocks_ + 4;
  const int candidates = static_cast<int>(candidates_block_.size());
  candidate_regime_.assign(static_cast<size_t>(candidates), 0);
  ring_.resize(static_cast<size_t>(ring));
  for (Block& b : ring_) {
    b.sum_rr = b.sum_rr_next = b.sum_tt = Eigen::VectorXd::Zero(m_);
    b.N.assign(static_cast<size_t>(candidates), Matrix10::Zero());
    b.g.assign(static_cast<size_t>(candidates), Vector10::Zero());
    b.g_next = b.g;
  }
  // Bonferroni over the tests of an hour: onsets x candidates per block.
  const double tests_per_hour = 3600.0 / o.block_time * onsets_ * std::max(1, candidates);
  threshold_ = ChiSquareQuantileEven(10, std::min(0.5, o.false_alarm_rate / tests_per_hour));
  w_ref_ = w_next_ = estimator.coefficients();
  reach_ = LongestSegment(model.tree());
  sigma_ = inv_var_ = r_ = r_next_ = Eigen::VectorXd::Zero(m_);
  A_ = Eigen::MatrixXd::Zero(m_, model.num_features());
  workspace_ = model.MakeWorkspace();
  scratch_.assign(static_cast<size_t>(std::max(ring, candidates)), 0.0);
}

bool PayloadEventDetector::testing() const {
  if (phase_ != Phase::kArmed) return false;
  for (int c = 0; c < static_cast<int>(candidates_block_.size()); ++c) {
    if (end_ - Regime(c) >= min_reference_blocks_) return true;
  }
  return false;
}

void PayloadEventDetector::StartBlock(double t0) {
  ++block_;
  Block& b = BlockAt(block_);
  b.t0 = t0;
  b.n = 0;
  b.sum_rr.setZero();
  b.sum_rr_next.setZero();
  b.sum_tt.setZero();
  for (Matrix10& N : b.N) N.setZero();
  for (Vector10& g : b.g) g.setZero();
  for (Vector10& g : b.g_next) g.setZero();
}

void PayloadEventDetector::Arm(const OnlineJointEstimator& estimator, double t) {
  w_ref_ = estimator.coefficients();  // same size: no allocation
  phase_ = Phase::kCalibrating;
  shadow_start_ = -1;
  calibration_start_ = block_ + 1;
  StartBlock(t);
}

void PayloadEventDetector::Sum(int c, std::int64_t from, std::int64_t to, Matrix10* N, Vector10* g) const {
  N->setZero();
  g->setZero();
  for (std::int64_t b = from; b < to; ++b) {
    *N += BlockAt(b).N[static_cast<size_t>(c)];
    *g += BlockAt(b).g[static_cast<size_t>(c)];
  }
}

// The sandwich: with the reference's fit d = N_R^-1 g_R and groups G of consecutive blocks, the
// groups' gradients u_G = g_G - N_G d have E[sum_G u_G^T M u_G] = phi sum_G (tr(M N_G) - tr((M N_G)^2))
// (M = N_R^-1) when each group's error has covariance phi N_G and groups are independent: phi is
// 1 for white noise of the scales s_j, larger for correlated or larger errors. Groups of 5 and 10
// blocks (0.5 and 1 s) cover correlation times up to a few tenths of a second (shorter ones
// included: single blocks would only give a less noisy estimate of those, at five times the cost,
// the per-block work's largest part); the larger estimate (of those with at least 3 groups) is taken.
double PayloadEventDetector::Inflation(int c, std::int64_t from, std::int64_t to) const {
  Matrix10 NR;
  Vector10 gR;
  Sum(c, from, to, &NR, &gR);
  const Matrix10 M = RegularizedInverse(NR);
  const Vector10 d = M * gR;
  double phi = 0.0;
  for (const int group : {5, 10}) {
    double num = 0, den = 0;
    int groups = 0;
    for (std::int64_t hi = to; hi - group >= from; hi -= group) {
      Matrix10 NG;
      Vector10 gG;
      Sum(c, hi - group, hi, &NG, &gG);
      const Vector10 u = gG - NG * d;
      num += u.dot(M * u);
      const Matrix10 MN = M * NG;
      den += MN.trace() - (MN * MN).trace();
      ++groups;
    }
    if (groups < 3 || !(den > 0)) continue;
    phi = std::max(phi, num / den);
  }
  // Floored at 0.5: an estimate far below 1 says s_j (measured at arming, against a reference
  // that was worse) is too large; it also comes from few groups, and would inflate the statistic.
  // With fewer than 3 groups (a short reference), 1.
  return phi > 0 && std::isfinite(phi) ? std::max(phi, 0.5) : 1.0;
}

std::int64_t PayloadEventDetector::Regime(int c) const {
  return std::max(regime_, candidate_regime_[static_cast<size_t>(c)]);
}

bool PayloadEventDetector::BestChange(std::int64_t last_onset, Fit* best) const {
  const std::int64_t end = end_;
  const int candidates = static_cast<int>(candidates_block_.size());
  for (int c = 0; c < candidates; ++c) {
    const std::int64_t regime = Regime(c);
    const std::int64_t first_onset =
        std::max({end - window_blocks_, regime + min_reference_blocks_, no_onset_before_});
    if (first_onset > last_onset) continue;
    // The inflation over the blocks before every window tested.
    const double phi = Inflation(c, std::max(regime, first_onset - reference_blocks_), first_onset);
    Fit mine;  // this candidate's best onset
    mine.kappa = phi;
    mine.regime = regime;
    Matrix10 NW, NR;
    Vector10 gW, gR;
    // Window [last_onset, end); reference [max(regime, last_onset - R), last_onset).
    Sum(c, last_onset, end, &NW, &gW);
    std::int64_t ref_lo = std::max(regime, last_onset - reference_blocks_);
    Sum(c, ref_lo, last_onset, &NR, &gR);
    for (std::int64_t b0 = last_onset; b0 >= first_onset; --b0) {
      if (b0 != last_onset) {  // the onset one block earlier: block b0 leaves the reference for the window
        const Block& moved = BlockAt(b0);
        NW += moved.N[static_cast<size_t>(c)];
        gW += moved.g[static_cast<size_t>(c)];
        NR -= moved.N[static_cast<size_t>(c)];
        gR -= moved.g[static_cast<size_t>(c)];
        const std::int64_t lo = std::max(regime, b0 - reference_blocks_);
        if (lo < ref_lo) {  // one older block joins the reference
          NR += BlockAt(lo).N[static_cast<size_t>(c)];
          gR += BlockAt(lo).g[static_cast<size_t>(c)];
          ref_lo = lo;
        }
      }
      const double lr = Explained(NW, gW) + Explained(NR, gR) - Explained(NW + NR, gW + gR);
      const double statistic = std::max(0.0, lr) / phi;
      if (statistic / threshold_ > mine.ratio) {
        mine.ratio = statistic / threshold_;
        mine.statistic = statistic;
        mine.candidate = c;
        mine.onset = mine.test_onset = b0;
      }
    }
    if (mine.ratio > best->ratio) *best = mine;
  }
  if (best->candidate < 0) return false;
  best->window_lo = best->onset;
  // The change at the best (candidate, onset): its bodies and covariance.
  Matrix10 NW, NR;
  Vector10 gW, gR, dW, dR;
  Sum(best->candidate, best->onset, end, &NW, &gW);
  Sum(best->candidate, std::max(best->regime, best->onset - reference_blocks_), best->onset, &NR, &gR);
  Explained(NW, gW, &dW);
  Explained(NR, gR, &dR);
  best->delta = dW - dR;
  best->d_ref = dR;
  best->cov = best->kappa * (RegularizedInverse(NW) + RegularizedInverse(NR));
  return true;
}

void PayloadEventDetector::Refit(Fit* fit, std::int64_t end) const {
  // Every candidate and every onset within kOnsetSearch blocks of the test's again, over
  // everything since. The change is the (link, onset) whose bodies before and after it explain the
  // data best: the largest g_W^T N_W^-1 g_W + g_R^T N_R^-1 g_R over the same blocks for every
  // choice (comparable log-likelihoods; not LR, whose pooled no-change term differs between
  // candidates). A short window may not yet tell neighbours apart (a body on link6 acts on joints
  // 1-6 as one on link7 while joint 7 hardly turns), and the test's onset is the one of its largest
  // ratio, which noise can move by a few blocks: both are chosen again at every block until the
  // event is emitted.
  //
  // The onset block holds the change somewhere within it, and the block before may too (the
  // likelihood's onset is the block of the change or the one after it): samples of both systems,
  // which no one body explains (on the tests' arm, a 2 kg pick-up 0.1 s into its block put link4
  // ahead of link7, and the mass 5 % off). The fit of the change leaves both out: the reference
  // ends before them, the window starts after them.
  // Every candidate over the same blocks: the reference starts where every candidate's does.
  std::int64_t regime = fit->regime;
  for (int c = 0; c < static_cast<int>(candidates_block_.size()); ++c) regime = std::max(regime, Regime(c));
  const std::int64_t ref_lo = std::max(regime, fit->test_onset - reference_blocks_);
  const std::int64_t first = std::max(ref_lo + 2, fit->test_onset - kOnsetSearch);
  const std::int64_t last = std::min(end - 2, fit->test_onset + kOnsetSearch);
  double best = -1.0;
  int best_candidate = -1;
  std::int64_t best_onset = fit->onset;
  std::vector<double>& per_candidate = scratch_;  // each candidate's best, for the runner-up
  const int candidates = static_cast<int>(candidates_block_.size());
  for (int c = 0; c < candidates; ++c) {
    per_candidate[static_cast<size_t>(c)] = -1.0;
    for (std::int64_t b0 = first; b0 <= last; ++b0) {
      Matrix10 NW, NR;
      Vector10 gW, gR;
      Sum(c, b0, end, &NW, &gW);
      Sum(c, ref_lo, b0, &NR, &gR);
      const double explained = Explained(NW, gW) + Explained(NR, gR);
      per_candidate[static_cast<size_t>(c)] = std::max(per_candidate[static_cast<size_t>(c)], explained);
      if (explained > best) {
        best = explained;
        best_candidate = c;
        best_onset = b0;
      }
    }
  }
  if (best_candidate < 0) return;  // no onset to choose from (cannot happen after min_settle_time)
  double second = -1.0;
  int second_candidate = -1;
  for (int c = 0; c < candidates; ++c) {
    if (c != best_candidate && per_candidate[static_cast<size_t>(c)] > second) {
      second = per_candidate[static_cast<size_t>(c)];
      second_candidate = c;
    }
  }
  const int c = best_candidate;
  const std::int64_t window_lo = std::min(best_onset + 1, end - 1), ref_hi = std::max(ref_lo + 1, best_onset - 1);
  Matrix10 NW, NR;
  Vector10 gW, gR, dW, dR;
  Sum(c, window_lo, end, &NW, &gW);
  Sum(c, ref_lo, ref_hi, &NR, &gR);
  const double phi = Inflation(c, ref_lo, ref_hi);
  fit->candidate = c;
  fit->onset = best_onset;
  fit->window_lo = window_lo;
  fit->kappa = phi;
  fit->statistic = std::max(0.0, Explained(NW, gW, &dW) + Explained(NR, gR, &dR) - Explained(NW + NR, gW + gR)) / phi;
  fit->delta = dW - dR;
  fit->d_ref = dR;
  fit->cov = phi * (RegularizedInverse(NW) + RegularizedInverse(NR));
  // The margin over the runner-up: how much less the next best link explains, over the inflation.
  fit->runner_up = second >= 0 ? (best - second) / phi : 0.0;
  fit->runner_up_candidate = second_candidate;
}

PayloadEvent PayloadEventDetector::MakeEvent(const OnlineJointEstimator& estimator, const Fit& fit, double t,
                                             bool settled) const {
  PayloadEvent ev;
  const RobotDynamics& model = estimator.model();
  const int body = candidates_body_[static_cast<size_t>(fit.candidate)];
  const Matrix10 L = ReportFrameMap(model.bodies()[body]);
  const Vector10 dpi = L * fit.delta;
  const Matrix10 C = L * fit.cov * L.transpose();
  ev.onset_time = BlockAt(fit.onset).t0;
  ev.detection_time = fired_t_;
  ev.settle_time = t;
  ev.settled = settled;
  ev.body = body;
  ev.link = model.bodies()[body].name;
  ev.added_pi = dpi;
  ev.added_mass = dpi[pi_index::kMass];
  ev.added_mass_std = std::sqrt(std::max(0.0, C(pi_index::kMass, pi_index::kMass)));
  const double dm = ev.added_mass;
  if (dm != 0.0) {
    const Vector3 dh = dpi.segment<3>(pi_index::kHx);
    ev.com = dh / dm;
    Eigen::Matrix<double, 3, 10> J = Eigen::Matrix<double, 3, 10>::Zero();  // J_c_dpi
    J.col(pi_index::kMass) = -dh / (dm * dm);
    J.block<3, 3>(0, pi_index::kHx) = Matrix3::Identity() / dm;
    ev.com_std = (J * C * J.transpose()).diagonal().cwiseMax(0.0).cwiseSqrt();
  } else {
    ev.com.setConstant(std::numeric_limits<double>::quiet_NaN());
    ev.com_std.setConstant(std::numeric_limits<double>::infinity());
  }
  ev.statistic = fit.statistic;
  ev.threshold = threshold_;
  ev.kappa = fit.kappa;
  ev.runner_up_margin = fit.runner_up;
  if (fit.runner_up_candidate >= 0) {
    ev.runner_up_body = candidates_body_[static_cast<size_t>(fit.runner_up_candidate)];
    ev.runner_up_link = model.bodies()[ev.runner_up_body].name;
  }
  for (std::int64_t b = fit.onset; b < end_; ++b) ev.num_samples += BlockAt(b).n;
  return ev;
}

void PayloadEventDetector::SetNoise(std::int64_t from, std::int64_t to) {
  // s_j: the median block RMS, floored at 1e-3 of the torque's RMS (as identify floors its noise
  // scales) and 1e-9.
  const int count = static_cast<int>(to - from);
  for (int j = 0; j < m_; ++j) {
    double tt = 0, n = 0;
    for (int k = 0; k < count; ++k) {
      const Block& b = BlockAt(from + k);
      scratch_[static_cast<size_t>(k)] = b.n > 0 ? std::sqrt(b.sum_rr[j] / b.n) : 0.0;
      tt += b.sum_tt[j];
      n += b.n;
    }
    std::nth_element(scratch_.begin(), scratch_.begin() + count / 2, scratch_.begin() + count);
    const double median = scratch_[static_cast<size_t>(count / 2)];
    sigma_[j] = std::max({median, 1e-3 * std::sqrt(n > 0 ? tt / n : 0.0), 1e-9});
    inv_var_[j] = 1.0 / (sigma_[j] * sigma_[j]);
  }
}

void PayloadEventDetector::Calibrate() {
  if (end_ - calibration_start_ < calibration_blocks_) return;
  SetNoise(calibration_start_, end_);
  phase_ = Phase::kArmed;
  regime_ = no_onset_before_ = end_;
  std::fill(candidate_regime_.begin(), candidate_regime_.end(), end_);
}

void PayloadEventDetector::Test(double t) {
  Fit best;
  if (!BestChange(end_ - 1, &best)) return;
  kappa_ = best.kappa;
  largest_ratio_ = std::max(largest_ratio_, best.ratio);
  if (best.ratio <= 1.0) return;
  pending_ = best;
  phase_ = Phase::kConfirming;
  fired_block_ = end_;
  fired_t_ = t;
  ++fired_;
}

void PayloadEventDetector::Confirm(double t) {
  if (end_ <= fired_block_) return;
  Matrix10 Nn;
  Vector10 gn;
  Sum(pending_.candidate, fired_block_, end_, &Nn, &gn);
  const Vector10& d = pending_.delta;
  const double expected = d.dot(Nn * d);
  const double gain = 2.0 * (gn - Nn * pending_.d_ref).dot(d) - expected;
  const double std = 2.0 * std::sqrt(pending_.kappa * std::max(0.0, expected));
  constexpr double kSigmas = 3.0;
  if (expected > 0 && gain >= 0.5 * expected && gain >= kSigmas * std) {
    phase_ = Phase::kSettling;
    confirmed_t_ = t;
    ++confirmed_;
  } else if ((0.5 * expected >= kSigmas * std && gain < 0.5 * expected) || t - fired_t_ >= options_.confirm_time) {
    phase_ = Phase::kArmed;  // refuted, or not confirmed in time: no event; not tested again from before it
    no_onset_before_ = fired_block_;
  }
}

void PayloadEventDetector::Settle(const OnlineJointEstimator& estimator, double t, std::optional<PayloadEvent>* emitted,
                                  bool force) {
  Refit(&pending_, end_);
  const RobotDynamics& model = estimator.model();
  const Matrix10 L = ReportFrameMap(model.bodies()[candidates_body_[static_cast<size_t>(pending_.candidate)]]);
  const Vector10 dpi = L * pending_.delta;
  const double dm = dpi[pi_index::kMass];
  const double dm_std = std::sqrt(std::max(0.0, (L * pending_.cov * L.transpose())(pi_index::kMass, pi_index::kMass)));
  // A payload: its mass known to mass_std_fraction, its COM within reach of the link (a ball of
  // the robot's longest segment about the link frame's origin, as RobotDynamics bounds a payload
  // effect's region: what a link can hold, a gripped object included).
  const bool within_reach = !(reach_ > 0.0) || (dm != 0.0 && (dpi.segment<3>(pi_index::kHx) / dm).norm() <= reach_);
  const bool settled = dm_std <= options_.mass_std_fraction * std::abs(dm) && within_reach;
  // A change whose added mass the data cannot tell from zero once min_settle_time has passed is
  // not a payload (a drift of the reference, a change of friction or of a sensor, a body on a link
  // whose mass the torques do not show): dropped at once, so that the test runs again.
  constexpr double kMassSigmas = 3.0;
  const bool massless = !(std::abs(dm) >= kMassSigmas * dm_std);
  if (!force && t - BlockAt(pending_.onset).t0 < options_.min_settle_time) return;
  if (!force && !settled && !massless && t - confirmed_t_ < options_.max_settle_time) return;
  phase_ = Phase::kArmed;
  // Not settled by max_settle_time (or the stream ended or broke off): reported only as a clear
  // mass change (its mass to 10 %, a 10-sigma change) within reach. Else no event.
  constexpr double kUnsettledMassSigmas = 10.0;
  if (!settled && !(std::abs(dm) >= kUnsettledMassSigmas * dm_std && within_reach)) {
    no_onset_before_ = fired_block_;
    return;
  }
  *emitted = MakeEvent(estimator, pending_, t, settled);
  // The reference model takes the change (the link's 10 coefficients += delta). The link's own
  // gradients since the change are corrected exactly (g_b -= N_b delta: its blocks' N are those of
  // its columns), so its next change (a put-down) is tested against a reference from the change
  // on; the other links' gradients would need the cross terms of their columns with this link's,
  // which are not kept: their references start now. A shadow begun before the change is dropped.
  const int c = pending_.candidate;
  w_ref_.segment<10>(10 * candidates_block_[static_cast<size_t>(c)]) += pending_.delta;
  for (std::int64_t b = pending_.window_lo; b < end_; ++b) {
    Block& block = BlockAt(b);
    block.g[static_cast<size_t>(c)].noalias() -= block.N[static_cast<size_t>(c)] * pending_.delta;
  }
  for (int k = 0; k < static_cast<int>(candidate_regime_.size()); ++k) {
    candidate_regime_[static_cast<size_t>(k)] = k == c ? pending_.window_lo : end_;
  }
  no_onset_before_ = pending_.window_lo;
  shadow_start_ = -1;
}

// The reference model follows the estimate without a blind span: w_next (the estimate when a
// shadow starts) collects its own gradients beside w_ref's (N does not depend on the model), and
// after min_reference_time of blocks it replaces w_ref if it predicted those blocks better (its
// squared normalized error smaller; out of sample: w_next is from data before them); else it is
// dropped. Then the next shadow starts. While the estimate still learns, the reference follows it
// every min_reference_time; after a payload event, the estimate (which mixes the samples before
// and after the change) is taken only once it predicts better than the reference that took the
// change; a shadow is decided only while no change is being confirmed or settled.
void PayloadEventDetector::Rebase(const OnlineJointEstimator& estimator) {
  if (phase_ != Phase::kArmed) {
    shadow_start_ = -1;
    return;
  }
  if (shadow_start_ < 0) {
    w_next_ = estimator.coefficients();
    shadow_start_ = end_;
    return;
  }
  if (end_ - shadow_start_ < min_reference_blocks_) return;
  double ref = 0, next = 0;
  for (std::int64_t b = shadow_start_; b < end_; ++b) {
    ref += BlockAt(b).sum_rr.dot(inv_var_);
    next += BlockAt(b).sum_rr_next.dot(inv_var_);
  }
  if (next < ref) {
    for (std::int64_t b = shadow_start_; b < end_; ++b) BlockAt(b).g.swap(BlockAt(b).g_next);
    w_ref_.swap(w_next_);
    // s_j stay those of arming: the reference span's blocks and the window's then share their
    // weights, and the sandwich's phi (below 1 when the new reference predicts better than s_j
    // says) scales the statistic to the errors as they are.
    regime_ = std::max(regime_, shadow_start_);
    no_onset_before_ = std::max(no_onset_before_, regime_);
  }
  shadow_start_ = -1;
}

// While a change is confirmed or settled the tests go on for onsets after the ones Refit may
// choose: a later change whose ratio beats the pending one's takes its place (the pending one is
// dropped, no event). Without it a weak firing (a drift of the reference, confirmed by the samples
// after it, whose mass then never settles) would hold the detector while a real put-down goes by,
// and Refit would give that put-down the weak firing's onset and link.
bool PayloadEventDetector::Supersede(double t) {
  const std::int64_t saved = no_onset_before_;
  no_onset_before_ = std::max(saved, pending_.test_onset + kOnsetSearch + 1);
  Fit next;
  const bool found = BestChange(end_ - 1, &next);
  no_onset_before_ = saved;
  if (!found || !(next.ratio > 1.0) || !(next.ratio > pending_.ratio)) return false;
  largest_ratio_ = std::max(largest_ratio_, next.ratio);
  pending_ = next;
  phase_ = Phase::kConfirming;
  fired_block_ = end_;
  fired_t_ = t;
  ++fired_;
  return true;
}

void PayloadEventDetector::EndBlock(const OnlineJointEstimator& estimator, double t,
                                    std::optional<PayloadEvent>* emitted) {
  end_ = block_ + 1;
  if ((phase_ == Phase::kConfirming || phase_ == Phase::kSettling) && Supersede(t)) return;
  switch (phase_) {
    case Phase::kCalibrating: Calibrate(); return;
    case Phase::kArmed: Test(t); break;
    case Phase::kConfirming: Confirm(t); break;
    default: break;
  }
  if (phase_ == Phase::kSettling) Settle(estimator, t, emitted, false);
  Rebase(estimator);
}

std::optional<PayloadEvent> PayloadEventDetector::Flush(const OnlineJointEstimator& estimator) {
  std::optional<PayloadEvent> emitted;
  if (phase_ != Phase::kSettling) return emitted;
  const double t0 = BlockAt(block_).t0;
  end_ = block_ + 1;  // the open block closes
  Settle(estimator, last_t_, &emitted, true);
  StartBlock(t0 + options_.block_time);
  return emitted;
}

std::optional<PayloadEvent> PayloadEventDetector::Observe(const OnlineJointEstimator& estimator,
                                                          const JointSample& s) {
  std::optional<PayloadEvent> emitted;
  if (s.q.size() != m_ || s.qd.size() != m_ || s.qdd.size() != m_ || s.tau.size() != m_ || !std::isfinite(s.t) ||
      !s.q.allFinite() || !s.qd.allFinite() || !s.qdd.allFinite() || !s.tau.allFinite()) {
    return emitted;
  }
  const double t = s.t;
  if (seen_ && (t - last_t_ > options_.max_window || t < last_t_)) {
    // A gap (or time going back): a confirmed change is concluded on the data before it, then
    // the detector arms again.
    emitted = Flush(estimator);
    phase_ = Phase::kWaiting;
    first_t_ = t;
  }
  if (!seen_) first_t_ = t;
  seen_ = true;
  last_t_ = t;
  if (phase_ == Phase::kWaiting) {
    const OnlineFit* fit = estimator.fit();
    if (t - first_t_ < options_.arm_time || (fit != nullptr && !fit->solved())) return emitted;
    Arm(estimator, t);
  } else if (t >= BlockAt(block_).t0 + options_.block_time) {
    const double t0 = BlockAt(block_).t0;
    EndBlock(estimator, t, &emitted);
    StartBlock(t - std::fmod(t - t0, options_.block_time));
  }

  // The sample's features: the estimator's own when it computed them for this sample (qdd
  // measured), else from the sample (its qdd derived by the stream's preprocessing).
  const Eigen::MatrixXd* features = s.qdd_measured ? estimator.torque_features() : nullptr;
  if (features == nullptr) {
    estimator.model().Features(s.q, s.qd, s.qdd, &workspace_, A_);
    features = &A_;
  }
  const Eigen::MatrixXd& A = *features;
  r_ = s.tau;
  r_.noalias() -= A * w_ref_;
  Block& b = BlockAt(block_);
  ++b.n;
  b.sum_rr += r_.cwiseAbs2();
  b.sum_tt += s.tau.cwiseAbs2();
  if (phase_ == Phase::kCalibrating) return emitted;
  const bool shadow = shadow_start_ >= 0;
  if (shadow) {
    r_next_ = s.tau;
    r_next_.noalias() -= A * w_next_;
    b.sum_rr_next += r_next_.cwiseAbs2();
  }
  const int candidates = static_cast<int>(candidates_block_.size());
  for (int c = 0; c < candidates; ++c) {
    const int col = 10 * candidates_block_[static_cast<size_t>(c)];
    Matrix10& N = b.N[static_cast<size_t>(c)];
    Vector10& g = b.g[static_cast<size_t>(c)];
    Vector10& g_next = b.g_next[static_cast<size_t>(c)];
    for (int i = 0; i < m_; ++i) {
      const auto a = A.row(i).segment<10>(col);
      if (a.isZero(0.0)) continue;  // a joint the body does not load
      N.noalias() += inv_var_[i] * a.transpose() * a;
      g.noalias() += (inv_var_[i] * r_[i]) * a.transpose();
      if (shadow) g_next.noalias() += (inv_var_[i] * r_next_[i]) * a.transpose();
    }
  }
  return emitted;
}

}  // namespace inertial
