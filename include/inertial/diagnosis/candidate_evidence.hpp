/// @file candidate_evidence.hpp
/// How the diagnoses (joint_diagnosis.hpp, body_diagnosis.hpp) judge a candidate effect: three
/// kinds of evidence, any of which can make it a suggestion, and one score that ranks them.
///
/// 1. Held-out size (explained_error.hpp): the candidate removes at least min_explained of the
///    held-out mean-square error (averaged over channels), the pooled error falls, some channel's
///    held-out RMS falls by min_gain of its measured RMS, and z below is positive for a common
///    effect, or reaches p ln(N C), the BIC bound for p parameters, for an ordinary one (see Prior
///    odds; a share of a short log's error can be large and still noise: on the paper's 63-sample
///    logs that was most false alarms). Catches effects that leave a
///    large residual; blind to effects that are small next to the torques or that the links absorb.
///
/// 2. Held-out significance. On the held-out rows (which no fit sees), the fall of the squared
///    error of channel c, in units of that channel's residual variance, is
///      z_c = N (1 - rms_c(with)^2 / rms_c(without)^2) / tau_c,
///    N the held-out samples and tau_c the integrated autocorrelation time of the noise on channel c
///    (1 + 2 sum of its autocorrelations while positive: the number of samples that carry one
///    independent residual), measured on a residual the missing effect does not colour: for robots
///    that of the widest model (every candidate, linear least squares), for a single body that of
///    the candidate's own cross-validated prediction. z = sum_c z_c is the log-likelihood gain of
///    the candidate on data it was not fitted to, counted in independent samples. For a candidate
///    the data do not need, z is O(1) and negative on average (a coefficient fitted to noise
///    raises the held-out error). A candidate is significant when z >= (p + 1) ln(N C) and it
///    removes at least kMinSignificantShare of the held-out error (with tens of thousands of rows
///    a fall of 0.1 % can be certain and still not worth a parameter). (p + 1) ln(N C) (C channels,
///    p the candidate's parameters) is a BIC-like bound (p ln of the rows) with one more ln(N C) of margin for the
///    number of candidates tested; a 6-parameter twist bias needs more than a 1-parameter offset,
///    as a chi-square of 6 degrees of freedom is larger than one of 1 under the null.
///    Why not a significance test on the training cost (a likelihood ratio or an F test): on a real
///    robot the residual is model error, coloured over hundreds of samples, and a training-cost
///    test that treats every sample as independent calls almost every effect significant. Dividing
///    by tau counts a coloured residual for what it is worth, and judging on held-out rows
///    rewards only what transfers to data the fit has not seen. It also guards noise-free data:
///    the residual there is smooth (integration and differentiation error), tau is large and z small.
///
/// 3. Plausibility (plausibility.hpp). Free links can imitate a missing effect: a link made 6 times
///    heavier than its URDF imitates a rotor's armature as well as the armature does. Each link's
///    departure from its URDF outside the prior tolerance t is its excess
///    log(factor) - log(1 + t) (the factor counted beyond the estimate's own uncertainty, so a
///    link bent only by noise has none); the model's implausibility B is the sum over links. A
///    candidate restores a share (B_without - B_with) / B_without of it (with B_without = 0:
///    -B_with / log(1 + t), negative if it bends links). A link whose plausibility cannot be
///    measured (a body at the edge of the map's range) counts kUnmeasurableExcess. Route 3 needs
///    B_without >= kMinExcess: links less than 1 % past the tolerance (beyond their 2-sigma
///    margins) are no evidence. With B_without > 0,
///    a candidate that restores at least half while not raising the held-out error by min_explained
///    or more is a missing effect: the data are explained as well, by believable bodies. This is the
///    prior of eq. 14 used as evidence, with the tolerance (not the regularizer's weight, which only
///    breaks ties the data leave open) as its scale.
///
/// No route but 1 suggests a candidate that bends the links further (B rising by more than
/// kMaxBend log(1 + t)): its small held-out gain may come from the bending. Route 1 may: a large,
/// held-out gain is the effect's own (Coulomb friction on a wrist, with links already far from a
/// wrong URDF, can move them further while explaining a third of the error).
///
/// Prior odds. Evidence is weighed against how common the effect is before any data are seen
/// (a Bayesian would add 2 ln of the prior odds to the bar):
///  - common: friction (viscous, Coulomb), a torque offset and rotor armature exist on nearly every
///    actuated joint of a real robot (gears, seals, current-based torque): held-out size with a
///    positive z suffices. On a real arm the residual is coloured over hundreds of samples, so z
///    stays small for effects the arm certainly has; the BIC bar would stop the loop early.
///  - ordinary: a payload, a single-body sensor's biases: size needs z >= p ln(N C).
///  - rare: a spring on a joint that has none (a spring of small stiffness and large rest angle
///    imitates an offset or a slow drift of any residual): both size (at twice min_explained) and
///    significance.
///
/// Ranking (what reports show): candidates the held-out data support (routes 1, 2) come first,
/// scored by explained; then those only plausibility supports (route 3), scored by restored; then
/// the rest, scored by explained. Each score less kParsimony (p - 1) for p parameters (near-ties
/// go to the simpler effect). The held-out data rank first because they measure the effect itself;
/// how much plausibility a candidate restores also depends on how the other missing effects bend
/// the links (a viscous term can straighten part of what Coulomb friction bent), so it decides only
/// where the held-out data cannot.
/// candidate_ranking.hpp applies this ranking (with the near-ties and alternatives the diagnoses
/// measure) for every diagnosis, batch and online.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "inertial/estimation/batch/joint_identification.hpp"
#include "inertial/inertia/plausibility.hpp"

namespace inertial {

/// See the file comment. Candidates that raise the links' implausibility by more than this share
/// of the tolerance's log are not suggested.
inline constexpr double kMaxBend = 0.1;
/// The smallest implausibility route 3 acts on: log(1.01), 1 % past the tolerance.
inline constexpr double kMinExcess = 0.00995;
/// The excess counted for a link whose plausibility cannot be measured (log-factor units: e^100).
inline constexpr double kUnmeasurableExcess = 100.0;
/// The smallest held-out share a significant candidate must remove (route 2): a quarter of the
/// default min_explained; an offset the links absorb removes about 1-2 % of its joint's.
inline constexpr double kMinSignificantShare = 0.005;
/// How common an effect is before any data are seen (see Prior odds).
enum class PriorOdds { kCommon, kOrdinary, kRare };

/// A rare kind's score is lowered by this (a spring ranks below an offset or friction that explains
/// nearly as much).
inline constexpr double kRareEffectPenalty = 0.02;

/// The integrated autocorrelation time of a residual series: 1 + 2 sum_{k>=1} rho_k, summed while
/// rho_k > 0 (at most to lag N/4); 1 for white noise, large for smooth series. >= 1; 1 for fewer
/// than 4 samples or a zero series. (The series is one channel over time, in time order.)
double IntegratedAutocorrelationTime(const Eigen::Ref<const Eigen::VectorXd>& residual);

/// Sum of the excess of the bodies flagged in `links` (plausibility.hpp).
double LinksImplausibility(const std::vector<BodyPlausibility>& bodies, const std::vector<bool>& links,
                           double tolerance);

struct EvidenceRules {
  double min_explained = 0.02;
  double min_gain = 0.005;
  double prior_tolerance = kDefaultPriorTolerance;
};

struct CandidateEvidence {
  double explained = 0.0;     ///< held-out mean-square share removed (explained_error.hpp)
  bool size_conditions = false;  ///< explained_error.hpp's three conditions hold (route 1 also needs z)
  double significance = 0.0;  ///< z (see the file comment)
  double threshold = 0.0;     ///< (p + 1) ln(N C)
  double size_bar = 0.0;      ///< the z route 1 needs: 0 (common), p ln(N C) (ordinary), the threshold (rare)
  double restored = 0.0;      ///< share of the links' implausibility removed
  double score = 0.0;         ///< within its group (see Ranking)
  bool by_size = false, by_significance = false, by_plausibility = false;
  bool suggested() const { return by_size || by_significance || by_plausibility; }
  /// 0: supported by the held-out data; 1: by plausibility only; 2: not supported.
  int group() const { return by_size || by_significance ? 0 : (by_plausibility ? 1 : 2); }
};

/// @param without, with held-out errors of the model without and with the candidate (same rows).
/// @param tau per channel, the model's (without) residual autocorrelation time.
/// @param samples held-out samples per channel (N).
/// @param implausibility_without, implausibility_with B of the two fits.
/// @param parameters the candidate's parameter count; @param odds how common its kind is.
CandidateEvidence JudgeCandidate(const TorqueErrors& without, const TorqueErrors& with, const Eigen::VectorXd& tau,
                                 int samples, double implausibility_without, double implausibility_with,
                                 int parameters, PriorOdds odds, const EvidenceRules& rules);

}  // namespace inertial
