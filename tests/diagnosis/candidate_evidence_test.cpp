// How a candidate effect is judged (candidate_evidence.hpp), against hand-worked values: the
// integrated autocorrelation time of short series worked by hand and of a seeded AR(1) series
// against its closed form (1 + phi) / (1 - phi); the links' implausibility summed by hand; and
// JudgeCandidate's explained share, significance z, thresholds, routes and scores on held-out
// errors made up so that each is a line of arithmetic.
#include "inertial/diagnosis/candidate_evidence.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>

#include "test_support.hpp"

namespace inertial {
namespace {

using testing::Rng;

// Held-out errors of two channels whose measured torque RMS is `measured` (relative_rms = rms /
// measured, total_rms pooled over the channels).
TorqueErrors Errors(double rms0, double rms1, double measured0 = 2.0, double measured1 = 5.0) {
  TorqueErrors e;
  e.rms = Eigen::Vector2d(rms0, rms1);
  e.relative_rms = Eigen::Vector2d(rms0 / measured0, rms1 / measured1);
  e.total_rms = std::sqrt(0.5 * (rms0 * rms0 + rms1 * rms1));
  return e;
}

TEST(CandidateEvidence, AutocorrelationTimeOfShortSeriesByHand) {
  // Fewer than 4 samples, or a series that is constant (zero once its mean is taken out): 1.
  EXPECT_EQ(IntegratedAutocorrelationTime(Eigen::Vector3d(1, 2, 3)), 1.0);
  EXPECT_EQ(IntegratedAutocorrelationTime(Eigen::VectorXd::Constant(10, 4.0)), 1.0);
  // +1 +1 -1 -1 +1 +1 -1 -1: c0 = 8, lag 1 sums to 1 (rho 1/8), lag 2 to -6 (stop): 1 + 2/8.
  Eigen::VectorXd square(8);
  square << 1, 1, -1, -1, 1, 1, -1, -1;
  EXPECT_NEAR(IntegratedAutocorrelationTime(square), 1.25, 1e-15);
  // A ramp 0..7 (r = -3.5..3.5): c0 = 42, lag 1 sums to 26.25, lag 2 to 11.5, and N / 4 = 2 lags.
  Eigen::VectorXd ramp(8);
  for (int i = 0; i < 8; ++i) ramp[i] = i;
  EXPECT_NEAR(IntegratedAutocorrelationTime(ramp), 1.0 + 2.0 * (26.25 + 11.5) / 42.0, 1e-14);
  // The mean is taken out first: an offset does not change it.
  EXPECT_NEAR(IntegratedAutocorrelationTime(ramp.array() + 100.0), 1.0 + 2.0 * (26.25 + 11.5) / 42.0, 1e-12);
}

TEST(CandidateEvidence, AutocorrelationTimeOfWhiteAndAr1Noise) {
  Rng rng(11);
  const int N = 40000;
  Eigen::VectorXd white(N), ar(N);
  const double phi = 0.8;
  double x = 0.0;
  for (int i = 0; i < N; ++i) {
    white[i] = rng.Normal();
    x = phi * x + rng.Normal();
    ar[i] = x;
  }
  const double tau_white = IntegratedAutocorrelationTime(white);
  EXPECT_GE(tau_white, 1.0);
  EXPECT_LT(tau_white, 1.1);
  // AR(1): rho_k = phi^k, so tau = 1 + 2 phi / (1 - phi) = (1 + phi) / (1 - phi) = 9.
  EXPECT_NEAR(IntegratedAutocorrelationTime(ar), (1 + phi) / (1 - phi), 0.1 * 9.0);
}

TEST(CandidateEvidence, LinksImplausibilitySumsTheFlaggedLinksExcess) {
  std::vector<BodyPlausibility> bodies(5);
  bodies[0].factor = 1.5;   // log(1.5) - log(1.1)
  bodies[1].factor = 1.05;  // inside the tolerance: 0
  bodies[2].factor = std::numeric_limits<double>::infinity();  // not measurable: kUnmeasurableExcess
  bodies[3].factor = 3.0;   // not a link: not counted
  bodies[4].factor = 2.0;   // log(2) - log(1.1)
  const std::vector<bool> links{true, true, true, false, true};
  EXPECT_NEAR(LinksImplausibility(bodies, links, 0.1),
              std::log(1.5 / 1.1) + kUnmeasurableExcess + std::log(2.0 / 1.1), 1e-12);
  // Flags shorter than the bodies: the rest do not count.
  EXPECT_NEAR(LinksImplausibility(bodies, {true}, 0.1), std::log(1.5 / 1.1), 1e-15);
  EXPECT_EQ(LinksImplausibility(bodies, {}, 0.1), 0.0);
}

// Channel 0's RMS falls from 1 to 0.8, channel 1's stays 2; N = 1000 held-out samples, tau (2, 1).
// explained = (1 - 0.64) / 2 = 0.18; z = 1000 * 0.36 / 2 = 180; threshold (p + 1) ln(2000).
TEST(CandidateEvidence, HeldOutGainByHand) {
  const TorqueErrors without = Errors(1.0, 2.0), with = Errors(0.8, 2.0);
  const Eigen::Vector2d tau(2.0, 1.0);
  const EvidenceRules rules;
  const CandidateEvidence e = JudgeCandidate(without, with, tau, 1000, 0.0, 0.0, 1, PriorOdds::kCommon, rules);
  EXPECT_NEAR(e.explained, 0.18, 1e-15);
  EXPECT_NEAR(e.significance, 180.0, 1e-12);
  EXPECT_NEAR(e.threshold, 2.0 * std::log(2000.0), 1e-12);
  EXPECT_EQ(e.size_bar, 0.0);
  EXPECT_TRUE(e.size_conditions);
  EXPECT_TRUE(e.by_size);
  EXPECT_TRUE(e.by_significance);
  EXPECT_FALSE(e.by_plausibility);  // no implausibility to restore
  EXPECT_TRUE(e.suggested());
  EXPECT_EQ(e.group(), 0);
  EXPECT_NEAR(e.score, 0.18, 1e-15);
  EXPECT_NEAR(e.restored, 0.0, 0.0);

  // Six parameters, an ordinary kind: route 1 needs z >= 6 ln(2000) = 45.6 (180 is); the score
  // pays kParsimony per extra parameter.
  const CandidateEvidence six = JudgeCandidate(without, with, tau, 1000, 0.0, 0.0, 6, PriorOdds::kOrdinary, rules);
  EXPECT_NEAR(six.size_bar, 6.0 * std::log(2000.0), 1e-12);
  EXPECT_NEAR(six.threshold, 7.0 * std::log(2000.0), 1e-12);
  EXPECT_TRUE(six.by_size);
  EXPECT_NEAR(six.score, 0.18 - 5 * 0.005, 1e-15);

  // A residual coloured over 1000 samples on channel 0: z = 1000 * 0.36 / 1000 = 0.36. Common: still
  // size (z > 0); ordinary: below p ln(N C), and below the significance threshold.
  const Eigen::Vector2d coloured(1000.0, 1.0);
  const CandidateEvidence common = JudgeCandidate(without, with, coloured, 1000, 0, 0, 1, PriorOdds::kCommon, rules);
  EXPECT_NEAR(common.significance, 0.36, 1e-14);
  EXPECT_TRUE(common.by_size);
  EXPECT_FALSE(common.by_significance);
  const CandidateEvidence ordinary = JudgeCandidate(without, with, coloured, 1000, 0, 0, 1, PriorOdds::kOrdinary, rules);
  EXPECT_FALSE(ordinary.suggested());
  EXPECT_EQ(ordinary.group(), 2);
  // Rare: size and significance both, and a lower score.
  const CandidateEvidence rare = JudgeCandidate(without, with, coloured, 1000, 0, 0, 2, PriorOdds::kRare, rules);
  EXPECT_FALSE(rare.suggested());
  EXPECT_NEAR(rare.score, 0.18 - 0.005 - kRareEffectPenalty, 1e-15);
  EXPECT_TRUE(JudgeCandidate(without, with, tau, 1000, 0, 0, 2, PriorOdds::kRare, rules).by_size);
}

TEST(CandidateEvidence, SizeConditionsEachCanFail) {
  const Eigen::Vector2d tau(1.0, 1.0);
  const EvidenceRules rules;
  // (a) explained 0.5 * (1 - 0.99^2) = 0.00995 < min_explained.
  EXPECT_FALSE(JudgeCandidate(Errors(1, 2), Errors(0.99, 2), tau, 1000, 0, 0, 1, PriorOdds::kCommon, rules).by_size);
  // (c) every channel's relative RMS falls by less than min_gain: measured RMS 1000 on channel 0
  // (a fall of 0.2 N m is 0.0002 of it), though explained is 0.18.
  TorqueErrors without = Errors(1, 2, 1000, 5), with = Errors(0.8, 2, 1000, 5);
  const CandidateEvidence e = JudgeCandidate(without, with, tau, 1000, 0, 0, 1, PriorOdds::kCommon, rules);
  EXPECT_NEAR(e.explained, 0.18, 1e-15);
  EXPECT_FALSE(e.size_conditions);
  EXPECT_FALSE(e.by_size);
  EXPECT_TRUE(e.by_significance);  // z = 360 needs no size
  // (b) the pooled error rises although the shares average positive: channel 0 from 0.2 to 0.1
  // (share 0.75), channel 1 from 2 to 2.1 (share -0.1025; pooled mean square 2.02 -> 2.21).
  without = Errors(0.2, 2.0);
  with = Errors(0.1, 2.1);
  ASSERT_GT(with.total_rms, without.total_rms);
  const CandidateEvidence pooled = JudgeCandidate(without, with, tau, 1000, 0, 0, 1, PriorOdds::kCommon, rules);
  EXPECT_NEAR(pooled.explained, 0.5 * ((1 - 0.25) + (1 - 1.1025)), 1e-14);
  EXPECT_FALSE(pooled.by_size);
  EXPECT_FALSE(pooled.by_significance);
}

TEST(CandidateEvidence, PlausibilityRouteAndBending) {
  const Eigen::Vector2d tau(1.0, 1.0);
  const EvidenceRules rules;  // tolerance kDefaultPriorTolerance
  const double unit = std::log1p(rules.prior_tolerance);
  // Held-out errors unchanged, links' implausibility 0.5 -> 0.1: restored 0.8, route 3 only.
  const CandidateEvidence p = JudgeCandidate(Errors(1, 2), Errors(1, 2), tau, 1000, 0.5, 0.1, 3, PriorOdds::kCommon, rules);
  EXPECT_NEAR(p.restored, 0.8, 1e-15);
  EXPECT_NEAR(p.explained, 0.0, 0.0);
  EXPECT_FALSE(p.by_size);
  EXPECT_TRUE(p.by_plausibility);
  EXPECT_EQ(p.group(), 1);
  EXPECT_NEAR(p.score, 0.8 - 2 * 0.005, 1e-15);
  // Below kMinExcess there is nothing to restore.
  EXPECT_FALSE(JudgeCandidate(Errors(1, 2), Errors(1, 2), tau, 1000, 0.009, 0.0, 1, PriorOdds::kCommon, rules)
                   .by_plausibility);
  // Straight links bent by a candidate: restored = -B_with / log(1 + t).
  const CandidateEvidence bend = JudgeCandidate(Errors(1, 2), Errors(0.8, 2), tau, 1000, 0.0, 0.2 * unit, 1,
                                                PriorOdds::kCommon, rules);
  EXPECT_NEAR(bend.restored, -0.2, 1e-15);
  // Bending more than kMaxBend log(1 + t) bars significance, not size.
  EXPECT_TRUE(bend.by_size);
  EXPECT_FALSE(bend.by_significance);
  const CandidateEvidence slight = JudgeCandidate(Errors(1, 2), Errors(0.8, 2), tau, 1000, 0.0, 0.05 * unit, 1,
                                                  PriorOdds::kCommon, rules);
  EXPECT_TRUE(slight.by_significance);
}

TEST(CandidateEvidence, NonFiniteAndMismatchedInputs) {
  const Eigen::Vector2d tau(1.0, 1.0);
  const EvidenceRules rules;
  const CandidateEvidence nan = JudgeCandidate(Errors(1, 2), Errors(std::nan(""), 2), tau, 1000, 0, 0, 1,
                                               PriorOdds::kCommon, rules);
  EXPECT_FALSE(nan.suggested());
  EXPECT_EQ(nan.score, -std::numeric_limits<double>::infinity());
  EXPECT_THROW(JudgeCandidate(Errors(1, 2), Errors(1, 2), Eigen::Vector3d::Ones(), 1000, 0, 0, 1, PriorOdds::kCommon,
                              rules),
               std::invalid_argument);
  EXPECT_THROW(JudgeCandidate(Errors(1, 2), Errors(1, 2), tau, 0, 0, 0, 1, PriorOdds::kCommon, rules),
               std::invalid_argument);
}

}  // namespace
}  // namespace inertial
