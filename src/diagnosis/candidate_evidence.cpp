#include "inertial/diagnosis/candidate_evidence.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "inertial/diagnosis/explained_error.hpp"

namespace inertial {

double IntegratedAutocorrelationTime(const Eigen::Ref<const Eigen::VectorXd>& residual) {
  const Eigen::Index N = residual.size();
  if (N < 4) return 1.0;
  const Eigen::VectorXd r = residual.array() - residual.mean();
  const double c0 = r.squaredNorm();
  if (!(c0 > 0.0) || !std::isfinite(c0)) return 1.0;
  double tau = 1.0;
  for (Eigen::Index k = 1; k <= N / 4; ++k) {
    const double rho = r.head(N - k).dot(r.tail(N - k)) / c0;
    if (!(rho > 0.0)) break;
    tau += 2.0 * rho;
  }
  return tau;
}

double LinksImplausibility(const std::vector<BodyPlausibility>& bodies, const std::vector<bool>& links,
                           double tolerance) {
  double b = 0.0;
  for (size_t e = 0; e < bodies.size() && e < links.size(); ++e) {
    if (!links[e]) continue;
    const double x = bodies[e].Excess(tolerance);
    b += std::isfinite(x) ? x : kUnmeasurableExcess;
  }
  return b;
}

CandidateEvidence JudgeCandidate(const TorqueErrors& without, const TorqueErrors& with, const Eigen::VectorXd& tau,
                                 int samples, double implausibility_without, double implausibility_with,
                                 int parameters, PriorOdds odds, const EvidenceRules& rules) {
  const bool rare = odds == PriorOdds::kRare;
  const Eigen::Index C = without.rms.size();
  if (C == 0 || with.rms.size() != C || tau.size() != C || samples <= 0) {
    throw std::invalid_argument("candidate evidence: channel counts or sample count do not match");
  }
  CandidateEvidence e;
  e.explained = ExplainedShare(without.rms, with.rms);
  for (Eigen::Index c = 0; c < C; ++c) {
    const double before = without.rms[c] * without.rms[c];
    if (before > 0.0) e.significance += samples * (1.0 - with.rms[c] * with.rms[c] / before) / std::max(1.0, tau[c]);
  }
  e.threshold = (parameters + 1) * std::log(static_cast<double>(samples) * static_cast<double>(C));
  const double unit = std::log1p(rules.prior_tolerance);
  e.restored = implausibility_without > 0.0 ? (implausibility_without - implausibility_with) / implausibility_without
                                            : -implausibility_with / unit;
  if (!std::isfinite(e.restored)) e.restored = 0.0;
  e.score = RankingKey(e.explained, parameters);
  if (!std::isfinite(e.explained) || !std::isfinite(e.significance) || !std::isfinite(e.restored)) {
    e.score = -std::numeric_limits<double>::infinity();
    return e;
  }
  const bool bends = implausibility_with > implausibility_without + kMaxBend * unit;
  const bool pooled_falls = with.total_rms < without.total_rms;
  const double bic = parameters * std::log(static_cast<double>(samples) * static_cast<double>(C));
  e.size_conditions =
      SupportedByHeldOutData(without, with, e.explained, (rare ? 2.0 : 1.0) * rules.min_explained, rules.min_gain);
  e.size_bar = odds == PriorOdds::kCommon ? 0.0 : (rare ? e.threshold : bic);
  const bool size = e.size_conditions && (odds == PriorOdds::kCommon ? e.significance > 0.0 : e.significance >= bic);
  const bool significant =
      pooled_falls && e.significance >= e.threshold && e.explained >= kMinSignificantShare && !bends;
  if (rare) {
    e.by_size = e.by_significance = size && e.significance >= e.threshold && !bends;
    e.score -= kRareEffectPenalty;
    return e;
  }
  e.by_size = size;
  e.by_significance = significant;
  e.by_plausibility = !bends && implausibility_without >= kMinExcess && e.restored >= 0.5 &&
                      e.explained > -rules.min_explained;
  if (e.group() == 1) e.score = RankingKey(e.restored, parameters);
  return e;
}

}  // namespace inertial
