#include "inertial/diagnosis/candidate_ranking.hpp"

#include <algorithm>
#include <stdexcept>

namespace inertial {

CandidateRanking RankCandidates(const std::vector<CandidateEvidence>& evidence, const RankingOptions& options) {
  const int n = static_cast<int>(evidence.size());
  if (!options.near_tie_simpler.empty() && static_cast<int>(options.near_tie_simpler.size()) != n) {
    throw std::invalid_argument("candidate ranking: near_tie_simpler must be empty or one entry per candidate");
  }
  CandidateRanking out;
  out.alternative_to.assign(n, -1);
  out.reasons.assign(n, RankReason::kUnsupported);
  // Rule 1: near-ties to a simpler, supported form.
  for (int i = 0; i < static_cast<int>(options.near_tie_simpler.size()); ++i) {
    const int s = options.near_tie_simpler[i];
    if (s < -1 || s >= n || s == i) throw std::invalid_argument("candidate ranking: a near-tie names no other candidate");
    if (s >= 0 && evidence[s].suggested()) {
      out.alternative_to[i] = s;
      out.reasons[i] = RankReason::kNearTieToSimpler;
    }
  }
  // Rule 2: suggestions (no alternative) first, then by group and score.
  const auto suggestion = [&](int i) { return evidence[i].suggested() && out.alternative_to[i] < 0; };
  const auto before = [&](int a, int b) {
    const bool sa = suggestion(a), sb = suggestion(b);
    if (sa != sb) return sa;
    if (evidence[a].group() != evidence[b].group()) return evidence[a].group() < evidence[b].group();
    return evidence[a].score > evidence[b].score;
  };
  out.order.resize(n);
  for (int i = 0; i < n; ++i) out.order[i] = i;
  std::stable_sort(out.order.begin(), out.order.end(), before);
  // Rule 3: alternatives to the top suggestion.
  if (n > 0 && evidence[out.order[0]].suggested() && options.same_as_top) {
    const int top = out.order[0];
    std::vector<int> others;
    for (int k = 1; k < n; ++k) {
      if (evidence[out.order[k]].suggested()) others.push_back(out.order[k]);
    }
    if (!others.empty()) {
      const std::vector<bool> same = options.same_as_top(top, others);
      if (same.size() != others.size()) {
        throw std::invalid_argument("candidate ranking: the alternatives test answered for another number of candidates");
      }
      for (size_t k = 0; k < others.size(); ++k) {
        if (!same[k]) continue;
        out.alternative_to[others[k]] = top;
        out.reasons[others[k]] = RankReason::kSameAsTop;
      }
      std::stable_sort(out.order.begin(), out.order.end(), before);
    }
  }
  // Rule 4: the suggestions.
  for (int i = 0; i < n; ++i) {
    if (!suggestion(i)) continue;
    if (options.model_converged) {
      out.reasons[i] = RankReason::kSuggested;
      ++out.num_suggestions;
    } else {
      out.reasons[i] = RankReason::kModelNotConverged;
    }
  }
  return out;
}

}  // namespace inertial
