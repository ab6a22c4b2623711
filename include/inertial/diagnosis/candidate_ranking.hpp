/// @file candidate_ranking.hpp
/// The one ranking of candidate effects (candidate_evidence.hpp, "Ranking"), shared by the batch
/// diagnoses (joint_diagnosis.hpp, body_diagnosis.hpp) and the online one (online_diagnosis.hpp):
/// given every candidate's evidence, the order in which they are shown, which of them are
/// suggestions, and why each is where it is.
///
/// Rules, in order:
///  1. Near-ties to a simpler nested form (only where the caller measures them, `near_tie_simpler`):
///     a richer form (asymmetric friction holds a Coulomb step, a spring an offset) that does not
///     beat its simpler form on the same joint by the caller's margin is that form's alternative
///     when the simpler one is supported. The online diagnosis measures them (its candidates are
///     fitted to the residual with the links not refitted, so a richer form can win by a little what
///     the links leave unevenly); the batch diagnoses refit the links and rely on the score's
///     parsimony (explained_error.hpp's kParsimony, candidate_evidence.hpp's kRareEffectPenalty).
///  2. Order: suggestions that are no alternative first; within each part by group (held-out data,
///     plausibility only, unsupported) then score, best first; ties keep the input order.
///  3. Alternatives to the top suggestion (only where the caller can test them, `same_as_top`):
///     every other supported candidate, fitted together with the top one, that the caller finds no
///     longer supported is the top's alternative (also one already an alternative by rule 1: it
///     then names the top). The order is then taken again (rule 2).
///  4. Suggestions: the candidates that are supported and no alternative; none when the model's own
///     fit did not converge (its candidates would all look good).
#pragma once

#include <functional>
#include <vector>

#include "inertial/diagnosis/candidate_evidence.hpp"

namespace inertial {

/// Why a candidate is where the ranking put it.
enum class RankReason {
  kSuggested,          ///< supported by the held-out data or the links' plausibility, no alternative
  kUnsupported,        ///< no evidence route supports it (candidate_evidence.hpp)
  kNearTieToSimpler,   ///< rule 1: no better than its simpler, supported form
  kSameAsTop,          ///< rule 3: together with the top suggestion it is no longer supported
  kModelNotConverged,  ///< supported, but the model's own fit did not converge (rule 4)
};

/// Rule 3's test: given the top suggestion and the other supported candidates (indices into the
/// evidence, in rank order), whether each is no longer supported next to the top one.
using SameAsTopTest = std::function<std::vector<bool>(int top, const std::vector<int>& others)>;

struct RankingOptions {
  /// Per candidate: the simpler candidate (index) it nests and does not beat by the caller's
  /// margin, or -1 (rule 1). Empty: no near-ties.
  std::vector<int> near_tie_simpler;
  /// Rule 3's test; empty: no alternatives to the top.
  SameAsTopTest same_as_top;
  /// Whether the model's own fit converged (rule 4).
  bool model_converged = true;
};

struct CandidateRanking {
  std::vector<int> order;              ///< indices into the evidence, best first
  std::vector<int> alternative_to;     ///< per candidate (input order): the one it is an alternative of, or -1
  std::vector<RankReason> reasons;     ///< per candidate (input order)
  int num_suggestions = 0;             ///< the first num_suggestions of `order` are the suggestions
};

/// Ranks candidates by the rules of the file comment. An empty list gives an empty ranking.
/// @throws std::invalid_argument if near_tie_simpler is neither empty nor one index (or -1) per
/// candidate, or same_as_top answers for a different number of candidates than it was asked about.
CandidateRanking RankCandidates(const std::vector<CandidateEvidence>& evidence, const RankingOptions& options = {});

}  // namespace inertial
