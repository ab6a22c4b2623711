// The one ranking of candidate effects (candidate_ranking.hpp), on evidence built by hand so that
// the correct order is known: a clear winner; a near-tie that goes to the simpler effect (by the
// score's parsimony, and by a measured near-tie to a nested form); a candidate refused by the
// support tests ranked after the supported ones whatever it explains; plausibility-only support
// after held-out support; alternatives to the top; a model that did not converge; an empty list.
#include "inertial/diagnosis/candidate_ranking.hpp"

#include <gtest/gtest.h>

#include <stdexcept>
#include <vector>

#include "inertial/diagnosis/explained_error.hpp"

namespace inertial {
namespace {

// Evidence of a candidate of `parameters` parameters removing `explained` of the held-out error,
// supported by the held-out data (route 1) or not; its score as JudgeCandidate sets it.
CandidateEvidence HeldOut(double explained, int parameters, bool supported) {
  CandidateEvidence e;
  e.explained = explained;
  e.size_conditions = supported;
  e.by_size = supported;
  e.score = RankingKey(explained, parameters);
  return e;
}

// Supported by plausibility only (route 3): scored by the share of implausibility restored.
CandidateEvidence ByPlausibility(double explained, double restored, int parameters) {
  CandidateEvidence e;
  e.explained = explained;
  e.restored = restored;
  e.by_plausibility = true;
  e.score = RankingKey(restored, parameters);
  return e;
}

TEST(CandidateRanking, EmptyListGivesAnEmptyRanking) {
  const CandidateRanking r = RankCandidates({});
  EXPECT_TRUE(r.order.empty());
  EXPECT_TRUE(r.alternative_to.empty());
  EXPECT_TRUE(r.reasons.empty());
  EXPECT_EQ(r.num_suggestions, 0);
  // The alternatives test is never asked about an empty list.
  RankingOptions o;
  o.same_as_top = [](int, const std::vector<int>&) -> std::vector<bool> {
    ADD_FAILURE() << "asked about no candidate";
    return {};
  };
  EXPECT_EQ(RankCandidates({}, o).num_suggestions, 0);
}

TEST(CandidateRanking, ClearWinnerFirst) {
  // viscous 3 %, coulomb 40 %, offset 10 %: coulomb, offset, viscous.
  const std::vector<CandidateEvidence> e = {HeldOut(0.03, 1, true), HeldOut(0.40, 1, true), HeldOut(0.10, 1, true)};
  const CandidateRanking r = RankCandidates(e);
  EXPECT_EQ(r.order, (std::vector<int>{1, 2, 0}));
  EXPECT_EQ(r.num_suggestions, 3);
  EXPECT_EQ(r.alternative_to, (std::vector<int>{-1, -1, -1}));
  for (RankReason why : r.reasons) EXPECT_EQ(why, RankReason::kSuggested);
}

TEST(CandidateRanking, NearTieGoesToTheSimplerEffectByParsimony) {
  // A spring (2 parameters) removing 10.3 % against an offset (1) removing 10.0 %: the spring's
  // score 0.103 - 0.005 = 0.098 is below the offset's 0.100.
  const std::vector<CandidateEvidence> e = {HeldOut(0.103, 2, true), HeldOut(0.100, 1, true)};
  EXPECT_NEAR(e[0].score, 0.098, 1e-15);
  const CandidateRanking r = RankCandidates(e);
  EXPECT_EQ(r.order, (std::vector<int>{1, 0}));
  EXPECT_EQ(r.num_suggestions, 2);
  // A spring that removes clearly more (20 %) wins.
  EXPECT_EQ(RankCandidates({HeldOut(0.20, 2, true), HeldOut(0.100, 1, true)}).order, (std::vector<int>{0, 1}));
}

TEST(CandidateRanking, MeasuredNearTieMakesTheRicherFormTheSimplersAlternative) {
  // asymmetric (0) scores above coulomb (1) but the caller measured it does not beat coulomb by
  // its margin: coulomb is the suggestion, asymmetric its alternative, shown after the suggestions.
  const std::vector<CandidateEvidence> e = {HeldOut(0.31, 2, true), HeldOut(0.30, 1, true), HeldOut(0.05, 1, true)};
  RankingOptions o;
  o.near_tie_simpler = {1, -1, -1};
  const CandidateRanking r = RankCandidates(e, o);
  EXPECT_EQ(r.order, (std::vector<int>{1, 2, 0}));
  EXPECT_EQ(r.num_suggestions, 2);
  EXPECT_EQ(r.alternative_to, (std::vector<int>{1, -1, -1}));
  EXPECT_EQ(r.reasons[0], RankReason::kNearTieToSimpler);
  // A simpler form the data do not support takes nothing: the richer one stays a suggestion.
  const std::vector<CandidateEvidence> f = {HeldOut(0.31, 2, true), HeldOut(0.30, 1, false)};
  o.near_tie_simpler = {1, -1};
  const CandidateRanking s = RankCandidates(f, o);
  EXPECT_EQ(s.order, (std::vector<int>{0, 1}));
  EXPECT_EQ(s.num_suggestions, 1);
  EXPECT_EQ(s.alternative_to, (std::vector<int>{-1, -1}));
  EXPECT_EQ(s.reasons[1], RankReason::kUnsupported);
}

TEST(CandidateRanking, RefusedBySupportTestRanksAfterTheSupported) {
  // The refused candidate explains the most (its held-out gain was not significant, or it bent the
  // links): it is no suggestion and comes after both supported ones.
  const std::vector<CandidateEvidence> e = {HeldOut(0.50, 1, false), HeldOut(0.04, 1, true), HeldOut(0.08, 1, true)};
  const CandidateRanking r = RankCandidates(e);
  EXPECT_EQ(r.order, (std::vector<int>{2, 1, 0}));
  EXPECT_EQ(r.num_suggestions, 2);
  EXPECT_EQ(r.reasons[0], RankReason::kUnsupported);
  EXPECT_EQ(r.reasons[1], RankReason::kSuggested);
}

TEST(CandidateRanking, PlausibilityOnlyAfterHeldOutSupport) {
  // Group 0 (held-out) before group 1 (plausibility, scored by restored 0.9) before group 2.
  const std::vector<CandidateEvidence> e = {ByPlausibility(0.01, 0.9, 1), HeldOut(0.60, 1, false),
                                            HeldOut(0.05, 1, true)};
  const CandidateRanking r = RankCandidates(e);
  EXPECT_EQ(r.order, (std::vector<int>{2, 0, 1}));
  EXPECT_EQ(r.num_suggestions, 2);
}

TEST(CandidateRanking, AlternativesToTheTopAreAskedOnlyAboutSupportedOnes) {
  const std::vector<CandidateEvidence> e = {HeldOut(0.10, 1, true), HeldOut(0.40, 1, true), HeldOut(0.90, 1, false),
                                            HeldOut(0.20, 1, true)};
  RankingOptions o;
  int calls = 0;
  o.same_as_top = [&](int top, const std::vector<int>& others) {
    ++calls;
    EXPECT_EQ(top, 1);
    EXPECT_EQ(others, (std::vector<int>{3, 0}));  // rank order, the unsupported one left out
    return std::vector<bool>{true, false};        // 3 explains what 1 explains
  };
  const CandidateRanking r = RankCandidates(e, o);
  EXPECT_EQ(calls, 1);
  EXPECT_EQ(r.order, (std::vector<int>{1, 0, 3, 2}));
  EXPECT_EQ(r.num_suggestions, 2);
  EXPECT_EQ(r.alternative_to, (std::vector<int>{-1, -1, -1, 1}));
  EXPECT_EQ(r.reasons[3], RankReason::kSameAsTop);
  // No supported candidate: nothing to ask.
  o.same_as_top = [&](int, const std::vector<int>&) {
    ADD_FAILURE() << "asked without a top suggestion";
    return std::vector<bool>{};
  };
  EXPECT_EQ(RankCandidates({HeldOut(0.5, 1, false), HeldOut(0.2, 1, false)}, o).num_suggestions, 0);
}

TEST(CandidateRanking, NothingSuggestedWhenTheModelDidNotConverge) {
  RankingOptions o;
  o.model_converged = false;
  const CandidateRanking r = RankCandidates({HeldOut(0.05, 1, true), HeldOut(0.40, 1, true)}, o);
  EXPECT_EQ(r.order, (std::vector<int>{1, 0}));  // still shown in order
  EXPECT_EQ(r.num_suggestions, 0);
  EXPECT_EQ(r.reasons[0], RankReason::kModelNotConverged);
}

TEST(CandidateRanking, TiesKeepTheInputOrder) {
  const CandidateRanking r = RankCandidates({HeldOut(0.1, 1, true), HeldOut(0.1, 1, true), HeldOut(0.1, 1, true)});
  EXPECT_EQ(r.order, (std::vector<int>{0, 1, 2}));
}

TEST(CandidateRanking, RefusesMalformedOptions) {
  const std::vector<CandidateEvidence> e = {HeldOut(0.1, 1, true), HeldOut(0.2, 1, true)};
  RankingOptions o;
  o.near_tie_simpler = {-1};
  EXPECT_THROW(RankCandidates(e, o), std::invalid_argument);
  o.near_tie_simpler = {0, -1};  // itself
  EXPECT_THROW(RankCandidates(e, o), std::invalid_argument);
  o.near_tie_simpler = {2, -1};  // out of range
  EXPECT_THROW(RankCandidates(e, o), std::invalid_argument);
  o.near_tie_simpler.clear();
  o.same_as_top = [](int, const std::vector<int>&) { return std::vector<bool>{}; };
  EXPECT_THROW(RankCandidates(e, o), std::invalid_argument);
}

}  // namespace
}  // namespace inertial
