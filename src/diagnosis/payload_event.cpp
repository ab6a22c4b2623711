#include "inertial/diagnosis/payload_event.hpp"

#include <Eigen/Cholesky>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

#include "inertial/estimation/fit_uncertainty.hpp"
#include "inertial/model/number_text.hpp"

namespace inertial {

namespace {

void Require(bool ok, const char* what, double value) {
  if (!ok) {
    throw std::invalid_argument(std::string("PayloadEventDetector: ") + what + " (got " + FormatNumber(value, 6) + ")");
  }
}

}  // namespace

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
  Require(std::isfinite(o.min_settle_time) && o.min_settle_time >= 0, "min_settle_time must be finite and >= 0",
          o.min_settle_time);
  Require(std::isfinite(o.max_settle_time) && o.max_settle_time > 0, "max_settle_time must be finite and positive",
          o.max_settle_time);
  Require(o.min_settle_time <= o.max_settle_time, "min_settle_time must not exceed max_settle_time", o.min_settle_time);
  Require(o.mass_std_fraction > 0 && o.mass_std_fraction <= 1, "mass_std_fraction must be in (0, 1]",
          o.mass_std_fraction);
  Require(std::isfinite(o.check_interval) && o.check_interval > 0, "check_interval must be finite and positive",
          o.check_interval);
  const RobotDynamics& model = estimator.model();
  w_run_ = estimator.coefficients();
  w_before_ = w_run_;
  residual_ = Eigen::VectorXd::Zero(model.num_dofs());
  A_ = Eigen::MatrixXd::Zero(model.num_dofs(), model.num_features());
  workspace_ = model.MakeWorkspace();
  for (int e = 0; e < static_cast<int>(model.bodies().size()); ++e) {
    const int b = model.bodies()[e].tree_body;
    bool seen = false;
    for (const Candidate& c : candidates_) seen = seen || c.tree_body == b;
    if (seen) continue;  // a payload effect: the same columns as its link, reported as the link
    Candidate c;
    c.tree_body = b;
    c.body = e;
    candidates_.push_back(c);
  }
  const UpdateCounters& c = estimator.estimator().counters();
  last_outliers_ = c[UpdateStatus::kOutlier];
  last_accepted_ = c.accepted();
  last_numerical_ = c[UpdateStatus::kNumerical];
  last_changes_ = estimator.estimator().changes_detected();
}

void PayloadEventDetector::Accumulate(const OnlineJointEstimator& estimator, const JointSample& s) {
  const RobotDynamics& model = estimator.model();
  model.Features(s.q, s.qd, s.qdd, &workspace_, A_);
  residual_ = s.tau;
  residual_.noalias() -= A_ * w_before_;
  rss_total_ += residual_.squaredNorm();
  ++num_samples_;
  for (Candidate& c : candidates_) {
    for (int i = 0; i < A_.rows(); ++i) {
      const Vector10 a = A_.row(i).segment<10>(10 * c.tree_body).transpose();
      c.N.noalias() += a * a.transpose();
      c.g.noalias() += a * residual_[i];
    }
  }
}

bool PayloadEventDetector::Solve(const OnlineJointEstimator& estimator, double t, PayloadEvent* ev) const {
  const int dofs = estimator.model().num_dofs();
  const double dof_samples = static_cast<double>(dofs) * num_samples_;
  if (dof_samples <= 10) return false;
  double best_rss = std::numeric_limits<double>::infinity(), second_rss = best_rss;
  const Candidate *best = nullptr, *second = nullptr;
  Vector10 best_dpi = Vector10::Zero();
  Matrix10 best_Ninv = Matrix10::Zero();
  for (const Candidate& c : candidates_) {
    const Eigen::LLT<Matrix10> llt(c.N);
    if (llt.info() != Eigen::Success) continue;
    const Vector10 dpi = llt.solve(c.g);
    if (!dpi.allFinite()) continue;
    const double rss = std::max(0.0, rss_total_ - c.g.dot(dpi));
    if (rss < best_rss) {
      second_rss = best_rss;
      second = best;
      best_rss = rss;
      best = &c;
      best_dpi = dpi;
      best_Ninv = llt.solve(Matrix10::Identity());
    } else if (rss < second_rss) {
      second_rss = rss;
      second = &c;
    }
  }
  if (best == nullptr) return false;
  const EstimatedBody& body = estimator.model().bodies()[best->body];
  const Matrix10 L = ReportFrameMap(body);
  const double s2 = best_rss / (dof_samples - 10);
  const Vector10 dpi = L * best_dpi;
  const Matrix10 C = s2 * L * best_Ninv * L.transpose();
  ev->onset_time = onset_;
  ev->detection_time = detection_;
  ev->settle_time = t;
  ev->body = best->body;
  ev->added_pi = dpi;
  ev->added_mass = dpi[pi_index::kMass];
  ev->added_mass_std = std::sqrt(std::max(0.0, C(pi_index::kMass, pi_index::kMass)));
  ev->residual_rms = std::sqrt(s2);
  ev->runner_up_rms = std::isfinite(second_rss) ? std::sqrt(second_rss / (dof_samples - 10)) : second_rss;
  ev->runner_up_body = second != nullptr ? second->body : -1;
  ev->num_samples = num_samples_;
  const double dm = ev->added_mass;
  if (dm != 0.0) {
    const Vector3 dh = dpi.segment<3>(pi_index::kHx);
    ev->com = dh / dm;
    Eigen::Matrix<double, 3, 10> J = Eigen::Matrix<double, 3, 10>::Zero();  // J_c_dpi
    J.col(pi_index::kMass) = -dh / (dm * dm);
    J.block<3, 3>(0, pi_index::kHx) = Matrix3::Identity() / dm;
    ev->com_std = (J * C * J.transpose()).diagonal().cwiseMax(0.0).cwiseSqrt();
  } else {
    ev->com.setConstant(std::numeric_limits<double>::quiet_NaN());
    ev->com_std.setConstant(std::numeric_limits<double>::infinity());
  }
  ev->settled = ev->added_mass_std <= options_.mass_std_fraction * std::abs(dm);
  return true;
}

PayloadEvent PayloadEventDetector::Finish(const OnlineJointEstimator& estimator, double t, bool cut_short) {
  PayloadEvent ev;
  pending_ = false;
  if (Solve(estimator, t, &ev)) {
    ev.link = estimator.model().bodies()[ev.body].name;
    if (ev.runner_up_body >= 0) ev.runner_up_link = estimator.model().bodies()[ev.runner_up_body].name;
    if (cut_short) ev.settled = false;
    return ev;
  }
  // No candidate's fit has a solution (the arm did not move enough): the change, without a body.
  ev.onset_time = onset_;
  ev.detection_time = detection_;
  ev.settle_time = t;
  ev.settled = false;
  ev.link = "(unknown)";
  const double nan = std::numeric_limits<double>::quiet_NaN();
  ev.added_mass = ev.added_mass_std = ev.residual_rms = ev.runner_up_rms = nan;
  ev.com.setConstant(nan);
  ev.com_std.setConstant(nan);
  ev.added_pi.setConstant(nan);
  ev.num_samples = num_samples_;
  return ev;
}

std::optional<PayloadEvent> PayloadEventDetector::Observe(const OnlineJointEstimator& estimator,
                                                          const JointSample& sample) {
  const RecursiveEstimator& est = estimator.estimator();
  const UpdateCounters& counts = est.counters();
  const std::uint64_t outliers = counts[UpdateStatus::kOutlier];
  const std::uint64_t accepted = counts.accepted();
  const std::uint64_t numerical = counts[UpdateStatus::kNumerical];
  const std::uint64_t changes = est.changes_detected();
  const double t = sample.t;
  std::optional<PayloadEvent> emitted;

  if (changes != last_changes_) {
    // The detector fired at this sample: the run's copy of w is the pre-change model.
    if (pending_) {  // cut short by this change: what the fit has so far
      emitted = Finish(estimator, t, /*cut_short=*/true);
    }
    last_changes_ = changes;
    ++changes_seen_;
    if (!in_run_) {  // no outlier seen (a skipped call): the best left is the current model
      w_run_ = estimator.coefficients();
      run_onset_ = t;
    }
    w_before_ = w_run_;
    for (Candidate& c : candidates_) {
      c.N.setZero();
      c.g.setZero();
    }
    rss_total_ = 0.0;
    num_samples_ = 0;
    pending_ = true;
    onset_ = run_onset_;
    detection_ = t;
    next_check_ = t + options_.min_settle_time;
  }

  // Runs of outliers: counters only, unless a run starts (w copied into its buffer).
  if (outliers != last_outliers_) {
    if (!in_run_) {
      w_run_ = estimator.coefficients();  // same size: no allocation
      run_onset_ = t;
      in_run_ = true;
    }
  } else if (accepted != last_accepted_ || numerical != last_numerical_) {
    in_run_ = false;
  }
  const bool sample_taken = accepted != last_accepted_;
  last_outliers_ = outliers;
  last_accepted_ = accepted;
  last_numerical_ = numerical;

  if (pending_ && sample_taken) Accumulate(estimator, sample);
  if (pending_ && !emitted && t >= next_check_) {
    next_check_ = t + options_.check_interval;
    const bool timed_out = t - detection_ >= options_.max_settle_time;
    PayloadEvent ev;
    const bool solved = Solve(estimator, t, &ev);
    if ((solved && ev.settled) || timed_out) emitted = Finish(estimator, t, false);
  }
  return emitted;
}

}  // namespace inertial
