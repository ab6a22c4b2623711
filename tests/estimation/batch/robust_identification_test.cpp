// Outlier rejection in batch identification (robust_identification.hpp), on a leg-like chain built in
// code (the core has no URDF reader; tests/formats/robust_identification_test.cpp uses the bundled leg).
#include "inertial/estimation/batch/robust_identification.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "inertial/inertia/closed_form_bodies.hpp"
#include "estimation/leg_chain.hpp"
#include "test_support.hpp"

namespace inertial {
namespace {

using testing::ExciteLeg;
using testing::Rng;

const std::vector<std::string>& kJoints = testing::kLegJoints;
KinematicTree Leg(const std::vector<InertialParams>& links) { return testing::LegChain(links); }
std::vector<InertialParams> PriorLinks() { return testing::LegPriorLinks(); }
std::vector<InertialParams> TrueLinks() { return testing::LegTrueLinks(); }
using testing::NoLinks;

bool Contains(const std::string& text, const std::string& fragment) { return text.find(fragment) != std::string::npos; }

struct Case {
  RobotDynamics model, truth;
  Eigen::VectorXd x_true;
};

Case MakeCase() {
  const std::vector<EffectSpec> e = ParseEffectList("viscous,coulomb:scale=0.05");
  Case c{RobotDynamics(Leg(PriorLinks()), kJoints, e, NoLinks()), RobotDynamics(Leg(TrueLinks()), kJoints, e, NoLinks()),
         Eigen::VectorXd()};
  Eigen::VectorXd coeffs = Eigen::VectorXd::Zero(c.truth.num_features() - c.truth.num_inertia_features());
  for (const EffectTerm& t : c.truth.effects()) {
    coeffs[t.first_feature - c.truth.num_inertia_features()] = t.kind == EffectKind::kViscous ? 0.3 : 0.8;
  }
  c.x_true = c.truth.ParametersFromEffectCoefficients(coeffs);
  return c;
}

std::vector<int> AllBut(int N, const std::vector<int>& rejected) {
  std::vector<int> kept;
  for (int i = 0; i < N; ++i) {
    if (std::find(rejected.begin(), rejected.end(), i) == rejected.end()) kept.push_back(i);
  }
  return kept;
}

std::string FirstReason(const OutlierReport& r) { return r.reasons.empty() ? "" : r.reasons[0]; }

double HeldOutRms(const Case& c, const Eigen::VectorXd& x, const JointSamples& test) {
  return CompareTorques(PredictJointTorques(c.model, x, test), test.tau).total_rms;
}

// Standard normal tail values: 1 - Phi(5) = 2.8665157e-7 and 1 - Phi(6) = 9.8658765e-10, so
// 0.005 / n equals them at n = 17442.8 and n = 5067973.5.
TEST(OutlierRejection, ChauvenetThresholdMatchesNormalTables) {
  EXPECT_EQ(ChauvenetThreshold(1), 5.0);       // Phi^-1(1 - 0.005) = 2.58: the floor of 5 holds
  EXPECT_EQ(ChauvenetThreshold(10000), 5.0);   // 4.9: still the floor
  EXPECT_NEAR(ChauvenetThreshold(17443), 5.0, 1e-5);
  EXPECT_GT(ChauvenetThreshold(17443), 5.0);
  EXPECT_NEAR(ChauvenetThreshold(5067973), 6.0, 1e-6);
  EXPECT_GT(ChauvenetThreshold(1000000000000LL), ChauvenetThreshold(5067973));
  EXPECT_THROW(ChauvenetThreshold(0), std::invalid_argument);
}

// The heavy-tailed (Laplace) bound: n exp(-1.4826 ln2 k) = 0.01, checked by putting k back in; it
// is the default wherever it exceeds the Gaussian one (every n of a real log).
TEST(OutlierRejection, HeavyTailThresholdLeavesAHundredthOfALaplaceResidual) {
  for (long long n : {1000LL, 30003LL, 35189LL, 3000000LL}) {
    const double k = HeavyTailThreshold(n);
    EXPECT_NEAR(static_cast<double>(n) * std::exp(-1.4826 * std::log(2.0) * k), 0.01, 1e-12) << n;
    EXPECT_EQ(DefaultOutlierThreshold(n), std::max(k, ChauvenetThreshold(n)));
    EXPECT_GT(k, ChauvenetThreshold(n));
  }
  EXPECT_NEAR(HeavyTailThreshold(30003), 14.52, 0.01);
  EXPECT_THROW(HeavyTailThreshold(0), std::invalid_argument);
}

TEST(OutlierRejection, SelectSamplesCopiesRowsInOrder) {
  Rng rng(1);
  const Case c = MakeCase();
  const JointSamples s = ExciteLeg(c.truth, c.x_true, 10, 0.01, 0.1, rng, 0.0);
  const JointSamples sub = SelectSamples(s, {1, 4, 9});
  ASSERT_EQ(sub.size(), 3);
  EXPECT_EQ(sub.joint_names, kJoints);
  EXPECT_EQ(sub.t[1], s.t[4]);
  EXPECT_EQ(sub.q.row(2), s.q.row(9));
  EXPECT_EQ(sub.qd.row(0), s.qd.row(1));
  EXPECT_EQ(sub.qdd.row(1), s.qdd.row(4));
  EXPECT_EQ(sub.tau.row(2), s.tau.row(9));
  EXPECT_EQ(SelectSamples(s, {}).size(), 0);
  EXPECT_THROW(SelectSamples(s, {10}), std::invalid_argument);
  EXPECT_THROW(SelectSamples(s, {-1}), std::invalid_argument);
}

TEST(OutlierRejection, RowsExceptAndRowRangeListTheRowsKept) {
  EXPECT_EQ(RowsExcept(6, {0, 3, 5}), (std::vector<int>{1, 2, 4}));
  EXPECT_EQ(RowsExcept(3, {}), (std::vector<int>{0, 1, 2}));
  EXPECT_EQ(RowsExcept(3, {0, 1, 2}), std::vector<int>{});
  EXPECT_EQ(RowsExcept(0, {}), std::vector<int>{});
  EXPECT_EQ(RowRange(2, 9, 3), (std::vector<int>{2, 5, 8}));
  EXPECT_EQ(RowRange(4, 7), (std::vector<int>{4, 5, 6}));
  EXPECT_EQ(RowRange(5, 5), std::vector<int>{});
}

// Clean data, with and without noise: nothing is rejected, and the fit is the plain one.
TEST(OutlierRejection, CleanDataLosesNoRow) {
  const Case c = MakeCase();
  for (const double noise : {0.0, 0.2}) {
    Rng rng(2);
    const JointSamples train = ExciteLeg(c.truth, c.x_true, 4000, 0.005, noise, rng, 0.0);
    const RobustIdentificationResult r = IdentifyJointModelRobust(c.model, train, JointIdentificationOptions());
    EXPECT_TRUE(r.outliers.rejected.empty()) << "noise " << noise << ": " << r.outliers.rejected.size() << " rejected, first: "
                                             << (r.outliers.reasons.empty() ? "" : r.outliers.reasons[0]);
    EXPECT_TRUE(r.outliers.settled);
    EXPECT_EQ(r.outliers.rounds, 1);
    EXPECT_EQ(r.outliers.threshold, DefaultOutlierThreshold(12000));  // 12000 residuals
    EXPECT_TRUE(r.fit.lm.converged());
    const JointIdentificationResult plain = IdentifyJointModel(c.model, AccumulateNormalEquations(c.model, train));
    EXPECT_EQ(r.fit.x, plain.x);
    // The scale floor is 1e-3 of each joint's RMS torque: without noise it decides; with noise the
    // MAD scale is the noise's standard deviation.
    const Eigen::VectorXd rms = (train.tau.colwise().squaredNorm() / train.size()).cwiseSqrt().transpose();
    for (int j = 0; j < 3; ++j) {
      if (noise == 0.0) {
        EXPECT_NEAR(r.outliers.scale[j], 1e-3 * rms[j], 1e-6 * rms[j]) << j;
      } else {
        EXPECT_NEAR(r.outliers.scale[j], noise, 0.05 * noise) << j;
      }
    }
  }
}

// Two runs laid end to end, one noise-free and one with 0.2 N m of noise (as a simulated baseline
// and a real run): judged by one spread over both, the noisy run's rows fall outside the quiet
// one's; judged run by run (OutlierOptions::run_starts) no row goes, each run's scale is its own
// (the fit's error for the quiet run; the noise for the other), and a glitch
// in the quiet run, well inside the noisy run's spread, is still found.
TEST(OutlierRejection, RunsAreScreenedEachByItsOwnSpread) {
  const Case c = MakeCase();
  Rng rng(4);
  const JointSamples quiet = ExciteLeg(c.truth, c.x_true, 3000, 0.005, 0.0, rng, 0.0);
  const JointSamples noisy = ExciteLeg(c.truth, c.x_true, 3000, 0.005, 0.2, rng, 0.0);
  JointSamples both = quiet;
  const int N = 6000;
  for (Eigen::MatrixXd* m : {&both.q, &both.qd, &both.qdd, &both.tau}) m->conservativeResize(N, Eigen::NoChange);
  both.t.conservativeResize(N);
  both.q.bottomRows(3000) = noisy.q;
  both.qd.bottomRows(3000) = noisy.qd;
  both.qdd.bottomRows(3000) = noisy.qdd;
  both.tau.bottomRows(3000) = noisy.tau;
  both.t.tail(3000) = noisy.t.array() + quiet.t[2999] + 1.0;
  const RobustIdentificationResult pooled = IdentifyJointModelRobust(c.model, both, JointIdentificationOptions());
  EXPECT_GT(pooled.outliers.rejected.size(), 500u) << "one spread over both runs";
  OutlierOptions by_run;
  by_run.run_starts = {0, 3000, N};
  both.tau(1000, 1) += 0.1;  // a glitch of half the noisy run's standard deviation, in the quiet run
  const RobustIdentificationResult r = IdentifyJointModelRobust(c.model, both, JointIdentificationOptions(), by_run);
  EXPECT_EQ(r.outliers.rejected, std::vector<int>{1000}) << FirstReason(r.outliers);
  EXPECT_EQ(r.outliers.rows_by_run, (std::vector<int>{3000, 3000}));
  EXPECT_EQ(r.outliers.rejected_by_run, (std::vector<int>{1, 0}));
  ASSERT_EQ(r.outliers.run_scale.rows(), 2);
  for (int j = 0; j < 3; ++j) {
    // The quiet run's residual is the fit's own error (the noisy run moves the unweighted fit):
    // seen 0.002-0.004 N m, a fiftieth of the noisy run's spread.
    EXPECT_LT(r.outliers.run_scale(0, j), 0.1 * r.outliers.run_scale(1, j)) << j;
    EXPECT_NEAR(r.outliers.run_scale(1, j), 0.2, 0.02) << j;
    EXPECT_EQ(r.outliers.scale[j], r.outliers.run_scale(0, j));
  }
  OutlierOptions bad;
  bad.run_starts = {0, 4000, 3000, N};
  EXPECT_THROW(IdentifyJointModelRobust(c.model, both, JointIdentificationOptions(), bad), std::invalid_argument);
}

// One glitched torque: exactly its row goes, and the fit is the plain fit without it (bit for bit).
// Seen: held-out RMS 0.00790 N m against 0.00797 for the fit of the clean log; the plain fit 197.
TEST(OutlierRejection, OneGlitchedTorqueIsRejectedAndTheFitIsThatOfTheOtherRows) {
  Rng rng(3);
  const Case c = MakeCase();
  JointSamples train = ExciteLeg(c.truth, c.x_true, 4000, 0.005, 0.2, rng, 0.0);
  const JointSamples test = ExciteLeg(c.truth, c.x_true, 2000, 0.005, 0.0, rng, 1.7);
  const JointIdentificationResult clean = IdentifyJointModel(c.model, AccumulateNormalEquations(c.model, train));
  train.tau(1234, 1) = 1e6;
  const RobustIdentificationResult r = IdentifyJointModelRobust(c.model, train, JointIdentificationOptions());
  EXPECT_EQ(r.outliers.rejected, std::vector<int>{1234});
  EXPECT_TRUE(r.outliers.non_finite.empty());
  ASSERT_EQ(r.outliers.reasons.size(), 1u);
  EXPECT_TRUE(Contains(r.outliers.reasons[0], "sample 1234 (t = 6.17 s): residual of the fit on hip -1e+06")) << r.outliers.reasons[0];
  const JointNormalEquations kept = AccumulateNormalEquations(c.model, SelectSamples(train, AllBut(4000, {1234})));
  EXPECT_EQ(r.equations.AtA, kept.AtA);
  EXPECT_EQ(r.equations.btb, kept.btb);
  EXPECT_EQ(r.equations.num_samples, 3999);
  EXPECT_EQ(r.fit.x, IdentifyJointModel(c.model, kept).x);
  const double clean_rms = HeldOutRms(c, clean.x, test), robust_rms = HeldOutRms(c, r.fit.x, test);
  const double plain_rms = HeldOutRms(c, IdentifyJointModel(c.model, AccumulateNormalEquations(c.model, train)).x, test);
  EXPECT_LT(robust_rms, 1.2 * clean_rms) << clean_rms;
  EXPECT_GT(plain_rms, 100 * clean_rms) << "the glitch must ruin the plain fit, or this test proves nothing";
}

// enabled = false: exactly IdentifyJointModel on every row, glitch included.
TEST(OutlierRejection, DisabledIsThePlainFitBitForBit) {
  Rng rng(4);
  const Case c = MakeCase();
  JointSamples train = ExciteLeg(c.truth, c.x_true, 2000, 0.005, 0.2, rng, 0.0);
  train.tau(700, 2) = 500.0;
  JointIdentificationOptions options;
  options.prior_weight = 0.05;
  OutlierOptions off;
  off.enabled = false;
  const RobustIdentificationResult r = IdentifyJointModelRobust(c.model, train, options, off);
  const JointNormalEquations eq = AccumulateNormalEquations(c.model, train);
  const JointIdentificationResult plain = IdentifyJointModel(c.model, eq, options);
  EXPECT_EQ(r.fit.x, plain.x);
  EXPECT_EQ(r.fit.x_initial, plain.x_initial);
  EXPECT_EQ(r.fit.data_cost, plain.data_cost);
  EXPECT_EQ(r.fit.lm.iterations, plain.lm.iterations);
  EXPECT_EQ(r.equations.AtA, eq.AtA);
  EXPECT_TRUE(r.outliers.rejected.empty());
  EXPECT_EQ(r.outliers.rounds, 0);
}

// Non-finite values and values whose regressor overflows are rejected before any statistics.
TEST(OutlierRejection, NonFiniteAndOverflowingRowsAreRejectedOutright) {
  Rng rng(5);
  const Case c = MakeCase();
  JointSamples train = ExciteLeg(c.truth, c.x_true, 3000, 0.005, 0.2, rng, 0.0);
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  train.qdd(10, 2) = nan;
  train.tau(20, 0) = -inf;
  train.qd(30, 1) = 1e300;   // qd^2 in the regressor overflows
  train.tau(40, 2) = 1e300;  // finite regressor, absurd residual
  const RobustIdentificationResult r = IdentifyJointModelRobust(c.model, train, JointIdentificationOptions());
  EXPECT_EQ(r.outliers.non_finite, (std::vector<int>{10, 20, 30}));
  EXPECT_EQ(r.outliers.rejected, (std::vector<int>{10, 20, 30, 40}));
  ASSERT_EQ(r.outliers.reasons.size(), 4u);
  EXPECT_EQ(r.outliers.reasons[0], "sample 10 (t = 0.05 s): non-finite qdd_knee");
  EXPECT_EQ(r.outliers.reasons[1], "sample 20 (t = 0.1 s): non-finite tau_abad");
  EXPECT_EQ(r.outliers.reasons[2], "sample 30 (t = 0.15 s): the regressor or the prior's prediction is not finite (qd_hip = 1e+300)");
  EXPECT_TRUE(Contains(r.outliers.reasons[3], "sample 40 (t = 0.2 s): residual of the fit on knee -1e+300")) << r.outliers.reasons[3];
  EXPECT_TRUE(r.fit.x.allFinite());
  EXPECT_TRUE(std::isfinite(r.fit.data_cost));
  EXPECT_TRUE(r.fit.lm.converged());
  EXPECT_TRUE(std::isfinite(r.equations.btb));
}

// Rows that only the prior explains badly: 200 rows (5 %) moving 6 times faster, where the friction
// the prior lacks (it has no effects) and the Coriolis terms dominate. The prior's round rejects
// them; the fit of the other rows explains them, and they come back.
TEST(OutlierRejection, RowsRejectedByThePriorComeBack) {
  Rng rng(9);
  const Case c = MakeCase();
  JointSamples train = ExciteLeg(c.truth, c.x_true, 4000, 0.005, 0.2, rng, 0.0);
  for (int i = 1000; i < 1200; ++i) {
    train.qd.row(i) *= 6.0;
    train.tau.row(i) = c.truth.InverseDynamics(c.x_true, train.q.row(i).transpose(), train.qd.row(i).transpose(),
                                               train.qdd.row(i).transpose()).transpose();
    for (int j = 0; j < 3; ++j) train.tau(i, j) += 0.2 * rng.Normal();
  }
  // k = 5 (the Gaussian bound of this log's 12000 residuals): the prior's round rejects fast rows.
  OutlierOptions one_round;
  one_round.max_rounds = 1;
  one_round.threshold = 5.0;
  const RobustIdentificationResult first = IdentifyJointModelRobust(c.model, train, {}, one_round);
  // One fit: the rows the prior rejected (seen: 79, all fast ones) stay out, and the report says the
  // set did not settle.
  EXPECT_GT(first.outliers.rejected.size(), 20u);
  for (int i : first.outliers.rejected) {
    EXPECT_TRUE(i >= 1000 && i < 1200) << i;
  }
  EXPECT_EQ(first.outliers.rounds, 1);
  EXPECT_FALSE(first.outliers.settled);
  EXPECT_EQ(first.equations.num_samples, 4000 - static_cast<int>(first.outliers.rejected.size()));
  // Rounds until settled: every row is back, and the fit is that of all rows.
  OutlierOptions gaussian;
  gaussian.threshold = 5.0;
  const RobustIdentificationResult r = IdentifyJointModelRobust(c.model, train, {}, gaussian);
  EXPECT_TRUE(r.outliers.rejected.empty()) << FirstReason(r.outliers);
  EXPECT_EQ(r.outliers.rounds, 2);
  EXPECT_TRUE(r.outliers.settled);
  EXPECT_EQ(r.fit.x, IdentifyJointModel(c.model, AccumulateNormalEquations(c.model, train)).x);
}

TEST(OutlierRejection, BadOptionsAndUnusableDataAreRefused) {
  Rng rng(6);
  const Case c = MakeCase();
  JointSamples train = ExciteLeg(c.truth, c.x_true, 50, 0.01, 0.1, rng, 0.0);
  OutlierOptions zero_rounds;
  zero_rounds.max_rounds = 0;
  EXPECT_THROW(IdentifyJointModelRobust(c.model, train, {}, zero_rounds), std::invalid_argument);
  OutlierOptions negative;
  negative.threshold = -1.0;
  EXPECT_THROW(IdentifyJointModelRobust(c.model, train, {}, negative), std::invalid_argument);
  JointSamples renamed = train;
  renamed.joint_names[0] = "other";
  EXPECT_THROW(IdentifyJointModelRobust(c.model, renamed, {}), std::invalid_argument);
  train.tau.col(1).setConstant(std::numeric_limits<double>::quiet_NaN());
  try {
    IdentifyJointModelRobust(c.model, train, {});
    ADD_FAILURE() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_TRUE(Contains(e.what(), "no usable sample (sample 0 (t = 0 s): non-finite tau_hip; sample 1")) << e.what();
  }
}

// A given threshold is used as is: a lower k rejects more rows of the same Gaussian residuals.
TEST(OutlierRejection, GivenThresholdIsUsed) {
  Rng rng(7);
  const Case c = MakeCase();
  const JointSamples train = ExciteLeg(c.truth, c.x_true, 4000, 0.005, 0.2, rng, 0.0);
  OutlierOptions low;
  low.threshold = 2.5;  // P(|Z| > 2.5) = 1.24 %: about 147 of 4000 rows (3 joints); seen 142
  const RobustIdentificationResult r = IdentifyJointModelRobust(c.model, train, {}, low);
  EXPECT_EQ(r.outliers.threshold, 2.5);
  EXPECT_GT(r.outliers.rejected.size(), 100u);
  EXPECT_LT(r.outliers.rejected.size(), 200u);
  EXPECT_EQ(r.equations.num_samples, 4000 - static_cast<int>(r.outliers.rejected.size()));
}

TEST(OutlierRejection, DescribeExtremeValuesNamesGlitchesAndNothingElse) {
  Rng rng(8);
  const Case c = MakeCase();
  JointSamples s = ExciteLeg(c.truth, c.x_true, 1000, 0.005, 0.2, rng, 0.0);
  EXPECT_TRUE(DescribeExtremeValues(s).empty());
  s.tau(400, 2) = 1e4;   // at most 1e5 robust scales (the noise alone makes the scale 0.2): an outlier, not absurd
  EXPECT_TRUE(DescribeExtremeValues(s).empty());
  s.tau(500, 1) = 1e300;
  s.qd(600, 0) = std::numeric_limits<double>::infinity();
  s.q(700, 2) = -3e12;
  const std::vector<std::string> items = DescribeExtremeValues(s);
  ASSERT_EQ(items.size(), 3u);
  EXPECT_EQ(items[0], "sample 600 (t = 3 s): qd_abad = inf (not finite)");
  EXPECT_TRUE(Contains(items[1], "sample 500 (t = 2.5 s): tau_hip = 1e+300, ")) << items[1];
  EXPECT_TRUE(Contains(items[2], "sample 700 (t = 3.5 s): q_knee = -3e+12, ")) << items[2];
  EXPECT_TRUE(Contains(items[2], " robust scales from the column's median ")) << items[2];
  EXPECT_EQ(DescribeExtremeValues(s, 1).size(), 1u);
}

}  // namespace
}  // namespace inertial
