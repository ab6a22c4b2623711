// The robot diagnosis's pieces (joint_diagnosis.hpp): torque errors from per-joint normal
// equations against the residuals computed row by row; the effect list once a candidate is taken
// (added, or replacing a joint's Coulomb step); the bent links; the hold-out split; and one
// diagnosis of the leg chain whose data hide viscous friction on the knee: the top suggestion is
// that effect, its fitted coefficient the true one, and with it the held-out error falls to the
// noise's standard deviation.
#include "inertial/diagnosis/joint_diagnosis.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "estimation/leg_chain.hpp"
#include "estimation/synthetic_regression.hpp"
#include "simulated_robot.hpp"
#include "test_support.hpp"

namespace inertial {
namespace {

using testing::RandomMatrix;
using testing::Rng;

TEST(JointDiagnosis, ErrorsFromNormalEquationsAreTheRowResiduals) {
  Rng rng(1);
  const int joints = 3, N = 50, F = 4;
  std::vector<Eigen::MatrixXd> A(joints);
  std::vector<Eigen::VectorXd> b(joints);
  std::vector<JointNormalEquations> eq(joints);
  for (int k = 0; k < joints; ++k) {
    A[k] = RandomMatrix(rng, N, F);
    b[k] = RandomMatrix(rng, N, 1);
    eq[k].AtA = A[k].transpose() * A[k];
    eq[k].Atb = A[k].transpose() * b[k];
    eq[k].btb = b[k].squaredNorm();
    eq[k].num_samples = N;
  }
  const Eigen::VectorXd w = RandomMatrix(rng, F, 1);
  const TorqueErrors e = ErrorsFromNormalEquations(eq, w);
  double sse = 0.0, sst = 0.0;
  for (int k = 0; k < joints; ++k) {
    const double s = (A[k] * w - b[k]).squaredNorm();
    EXPECT_NEAR(e.rms[k], std::sqrt(s / N), 1e-12);
    EXPECT_NEAR(e.relative_rms[k], std::sqrt(s / N) / std::sqrt(b[k].squaredNorm() / N), 1e-12);
    sse += s;
    sst += b[k].squaredNorm();
  }
  EXPECT_NEAR(e.total_rms, std::sqrt(sse / (N * joints)), 1e-12);
  EXPECT_NEAR(e.total_relative_rms, std::sqrt(sse / sst), 1e-12);
  // A joint whose measured torque is zero has no relative error.
  eq[1].Atb.setZero();
  eq[1].btb = 0.0;
  EXPECT_TRUE(std::isnan(ErrorsFromNormalEquations(eq, w).relative_rms[1]));
  EXPECT_THROW(ErrorsFromNormalEquations({}, w), std::invalid_argument);
}

TEST(JointDiagnosis, EffectsWithACandidateAddedOrReplacingCoulomb) {
  const std::vector<std::string> joints = testing::kLegJoints;
  const std::vector<EffectSpec> effects = ParseEffectList("viscous,coulomb");
  CandidateResult added;
  added.spec = ParseEffectList("offset@hip").at(0);
  std::vector<EffectSpec> with = EffectsWithCandidate(effects, joints, added);
  ASSERT_EQ(with.size(), 3u);
  EXPECT_EQ(with[0].kind, EffectKind::kViscous);
  EXPECT_EQ(with[0].target, "");
  EXPECT_EQ(with[1].kind, EffectKind::kCoulomb);
  EXPECT_EQ(with[2].kind, EffectKind::kOffset);
  EXPECT_EQ(with[2].target, "hip");

  // A sigmoid on the knee replaces the knee's Coulomb step: every all-joint effect is written out
  // per joint, and coulomb@knee is gone.
  CandidateResult sigmoid;
  sigmoid.spec = ParseEffectList("sigmoid@knee").at(0);
  sigmoid.replaces = "coulomb@knee";
  with = EffectsWithCandidate(effects, joints, sigmoid);
  std::vector<std::string> items;
  for (const EffectSpec& e : with) items.push_back(std::string(ToString(e.kind)) + "@" + e.target);
  EXPECT_EQ(items, (std::vector<std::string>{"viscous@abad", "viscous@hip", "viscous@knee", "coulomb@abad",
                                             "coulomb@hip", "sigmoid@knee"}));
}

TEST(JointDiagnosis, BentLinksAreTheLinksOutsideTheTolerance) {
  JointDiagnosis d;
  d.prior_tolerance = 0.5;
  d.body_names = {"a", "rotor@b", "c", "d"};
  d.links = {true, false, true, true};
  d.plausibility.resize(4);
  d.plausibility[0].factor = 1.6;  // bent
  d.plausibility[1].factor = 9.0;  // a rotor, not a link
  d.plausibility[2].factor = 1.5;  // at the tolerance: within
  d.plausibility[3].factor = 2.0;  // bent
  EXPECT_EQ(BentLinks(d), (std::vector<std::string>{"a", "d"}));
}

TEST(JointDiagnosis, SplitHoldoutKeepsTheLastShare) {
  JointSamples data;
  data.joint_names = {"j"};
  const int N = 10;
  data.t = Eigen::VectorXd::LinSpaced(N, 0.0, 9.0);
  data.q = data.t;
  data.qd = 2.0 * data.t;
  data.qdd = 3.0 * data.t;
  data.tau = 4.0 * data.t;
  JointSamples train, validation;
  SplitHoldout(data, 0.3, &train, &validation);
  ASSERT_EQ(train.size(), 7);
  ASSERT_EQ(validation.size(), 3);
  EXPECT_EQ(validation.t[0], 7.0);
  EXPECT_EQ(validation.tau(2, 0), 36.0);
  EXPECT_EQ(train.qd(6, 0), 12.0);
  EXPECT_EQ(validation.joint_names, data.joint_names);
  EXPECT_THROW(SplitHoldout(data, 0.0, &train, &validation), std::invalid_argument);
  EXPECT_THROW(SplitHoldout(data, 1.0, &train, &validation), std::invalid_argument);
  EXPECT_THROW(SplitHoldout(data, 0.1, &train, &validation), std::invalid_argument);  // 1 held-out sample
  EXPECT_THROW(SplitHoldout(data, 0.9, &train, &validation), std::invalid_argument);  // 1 training sample
}

// The leg chain simulated with viscous friction b = 0.5 N m s / rad on the knee, links 10 % off
// their priors, torque noise 0.02 N m; the links-only model is diagnosed.
TEST(JointDiagnosis, FindsViscousFrictionHiddenOnTheKnee) {
  const auto make = [](const std::vector<EffectSpec>& effects) {
    return RobotDynamics(testing::LegChain(testing::LegPriorLinks()), testing::kLegJoints, effects, testing::NoLinks());
  };
  const RobotDynamics truth = make(ParseEffectList("viscous@knee"));
  const double b = 0.5, sigma = 0.02;
  const Eigen::VectorXd x_true = testing::TrueParameters(truth, {b}, 7, 0.1);
  const testing::SimulatedLogs logs = testing::SimulateLogs(truth, x_true, sigma, 12.0, 7, 100);
  JointDiagnosisOptions options;
  options.threads = 2;
  const JointDiagnosis d = DiagnoseJointModel(make, {}, {}, logs.train, logs.test, options);
  ASSERT_GE(d.num_suggestions, 1);
  const CandidateResult& top = d.candidates[0];
  EXPECT_EQ(top.name, "viscous@knee");
  EXPECT_EQ(top.joint, "knee");
  EXPECT_TRUE(top.evidence.suggested());
  ASSERT_EQ(top.values.size(), 1u);
  EXPECT_NEAR(top.values[0], b, 0.05 * b);
  // Without it the knee's held-out error is well above the noise; with it, at the noise.
  EXPECT_GT(d.fit_validation.rms[2], 3 * sigma);
  EXPECT_LT(top.validation.rms[2], 1.3 * sigma);
  EXPECT_LT(top.validation.total_rms, 1.3 * sigma);
  EXPECT_EQ(d.train_samples, logs.train.size());
  EXPECT_EQ(d.validation_samples, logs.test.size());
}

}  // namespace
}  // namespace inertial
