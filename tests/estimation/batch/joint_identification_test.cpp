#include "inertial/estimation/batch/joint_identification.hpp"

#include <gtest/gtest.h>

#include <Eigen/QR>
#include <cmath>

#include "inertial/inertia/closed_form_bodies.hpp"
#include "inertial/inertia/consistency.hpp"
#include "estimation/leg_chain.hpp"
#include "test_support.hpp"

namespace inertial {
namespace {

using testing::Rng;

const std::vector<std::string>& kJoints = testing::kLegJoints;
KinematicTree Leg(const std::vector<InertialParams>& links) { return testing::LegChain(links); }
std::vector<InertialParams> PriorLinks() { return testing::LegPriorLinks(); }
std::vector<InertialParams> TrueLinks() { return testing::LegTrueLinks(); }
using testing::ExciteLeg;
using testing::NoLinks;

struct Case {
  RobotDynamics model, truth;
  Eigen::VectorXd x_true;
};

Case MakeCase(const std::string& effects) {
  const std::vector<EffectSpec> e = ParseEffectList(effects);
  Case c{RobotDynamics(Leg(PriorLinks()), kJoints, e, NoLinks()), RobotDynamics(Leg(TrueLinks()), kJoints, e, NoLinks()),
         Eigen::VectorXd()};
  // True effect coefficients: b = 0.3, bc = 0.8 on every joint where present.
  Eigen::VectorXd coeffs = Eigen::VectorXd::Zero(c.truth.num_features() - c.truth.num_inertia_features());
  for (const EffectTerm& t : c.truth.effects()) {
    coeffs[t.first_feature - c.truth.num_inertia_features()] = t.kind == EffectKind::kViscous ? 0.3 : 0.8;
  }
  c.x_true = c.truth.ParametersFromEffectCoefficients(coeffs);
  return c;
}

// Noise-free data: the fit explains the torques and predicts a different trajectory (so it found the
// identifiable combinations), and the effects, which are identifiable, are recovered.
TEST(JointIdentification, RecoversIdentifiableDynamicsWithoutNoise) {
  Rng rng(31);
  const Case c = MakeCase("viscous,coulomb:scale=0.05");
  const JointSamples train = ExciteLeg(c.truth, c.x_true, 4000, 0.005, 0.0, rng, 0.0);
  const JointSamples test = ExciteLeg(c.truth, c.x_true, 2000, 0.005, 0.0, rng, 1.7);
  JointIdentificationOptions options;
  options.prior_weight = 1e-8;
  const JointIdentificationResult r = IdentifyJointModel(c.model, AccumulateNormalEquations(c.model, train), options);
  EXPECT_TRUE(r.lm.converged()) << ToString(r.lm.reason);
  const TorqueErrors prior = CompareTorques(PredictJointTorques(c.model, Eigen::VectorXd::Zero(c.model.num_parameters()), test), test.tau);
  const TorqueErrors fit = CompareTorques(PredictJointTorques(c.model, r.x, test), test.tau);
  EXPECT_GT(prior.total_relative_rms, 0.05);
  EXPECT_LT(fit.total_relative_rms, 1e-4) << "prior " << prior.total_relative_rms;
  for (int k = 0; k < static_cast<int>(c.model.effects().size()); ++k) {
    const double expected = c.model.effects()[k].kind == EffectKind::kViscous ? 0.3 : 0.8;
    EXPECT_NEAR(c.model.EffectValues(k, r.x)[0], expected, 1e-3) << k;
  }
}

// With noise of 0.2 N m the validation error falls to the noise floor, every body stays consistent,
// and unregularized linear least squares on the same data gives an impossible body.
TEST(JointIdentification, ReachesTheNoiseFloorWithConsistentBodies) {
  Rng rng(32);
  const Case c = MakeCase("viscous");
  const double sigma = 0.2;
  const JointSamples train = ExciteLeg(c.truth, c.x_true, 1000, 0.005, sigma, rng, 0.0);
  const JointSamples test = ExciteLeg(c.truth, c.x_true, 2000, 0.005, sigma, rng, 1.7);
  const JointNormalEquations eq = AccumulateNormalEquations(c.model, train);
  const JointIdentificationResult r = IdentifyJointModel(c.model, eq);
  EXPECT_TRUE(r.lm.converged()) << ToString(r.lm.reason);
  const TorqueErrors fit = CompareTorques(PredictJointTorques(c.model, r.x, test), test.tau);
  // The best possible RMS is sigma; 36 parameters fitted from 3000 torques add about 1 %.
  EXPECT_LT(fit.total_rms, 1.05 * sigma);
  EXPECT_GT(fit.total_rms, 0.9 * sigma);
  for (int e = 0; e < static_cast<int>(c.model.bodies().size()); ++e) {
    EXPECT_TRUE(CheckConsistency(c.model.BodyInertia(e, r.x)).fully_consistent()) << c.model.bodies()[e].name;
  }
  // Linear least squares on pi (minimum-norm, the usual pseudo-inverse): some body is inconsistent.
  const Eigen::VectorXd w_lls = eq.AtA.completeOrthogonalDecomposition().solve(eq.Atb);
  int inconsistent = 0;
  for (int b = 0; b < 3; ++b) {
    inconsistent += !CheckConsistency(InertialParams::FromVector(w_lls.segment<10>(10 * b))).fully_consistent();
  }
  EXPECT_GT(inconsistent, 0);
}

TEST(JointIdentification, RejectsSamplesThatDoNotMatchTheModel) {
  const Case c = MakeCase("");
  JointSamples s;
  s.joint_names = {"abad", "knee", "hip"};
  EXPECT_THROW(AccumulateNormalEquations(c.model, s), std::invalid_argument);
  EXPECT_THROW(CompareTorques(Eigen::MatrixXd(2, 3), Eigen::MatrixXd(3, 3)), std::invalid_argument);
}

// Per-joint statistics: each joint's squared error from them equals the squared error of that
// joint's predicted torques computed sample by sample, and they sum to the pooled statistics.
TEST(JointIdentification, JointwiseStatisticsGiveEachJointsError) {
  Rng rng(33);
  const Case c = MakeCase("viscous,coulomb:scale=0.05");
  const JointSamples data = ExciteLeg(c.truth, c.x_true, 700, 0.005, 0.1, rng, 0.4);
  const std::vector<JointNormalEquations> per = AccumulateJointwiseNormalEquations(c.model, data);
  const JointNormalEquations total = AccumulateNormalEquations(c.model, data);
  ASSERT_EQ(per.size(), 3u);
  Eigen::MatrixXd AtA = Eigen::MatrixXd::Zero(total.AtA.rows(), total.AtA.cols());
  for (const JointNormalEquations& e : per) AtA += e.AtA;
  EXPECT_LT((AtA - total.AtA).norm(), 1e-10 * total.AtA.norm());
  Eigen::VectorXd x = Eigen::VectorXd::Zero(c.model.num_parameters());
  for (int i = 0; i < x.size(); ++i) x[i] = rng.Uniform(-0.2, 0.2);
  const Eigen::MatrixXd err = PredictJointTorques(c.model, x, data) - data.tau;
  const Eigen::VectorXd w = c.model.Coefficients(x);
  for (int k = 0; k < 3; ++k) {
    const double direct = err.col(k).squaredNorm();
    EXPECT_NEAR(SquaredError(per[k], w), direct, 1e-8 * direct) << k;
  }
}

// Frozen bodies stay exactly at their priors while the rest is fitted: with the links frozen at
// the truth, the effects come out exactly; with the links frozen at a wrong prior, the fit is worse
// than with free links.
TEST(JointIdentification, FrozenBodiesStayAtTheirPriors) {
  Rng rng(34);
  const Case c = MakeCase("viscous,coulomb:scale=0.05");
  const JointSamples train = ExciteLeg(c.truth, c.x_true, 2000, 0.005, 0.0, rng, 0.0);
  const RobotDynamics at_truth(Leg(TrueLinks()), kJoints, ParseEffectList("viscous,coulomb:scale=0.05"), NoLinks());
  JointIdentificationOptions options;
  options.frozen_bodies = {true, true, true};
  const JointIdentificationResult exact = IdentifyJointModel(at_truth, AccumulateNormalEquations(at_truth, train), options);
  EXPECT_EQ(exact.x.head(30).cwiseAbs().maxCoeff(), 0.0);
  for (int k = 0; k < static_cast<int>(at_truth.effects().size()); ++k) {
    const double expected = at_truth.effects()[k].kind == EffectKind::kViscous ? 0.3 : 0.8;
    EXPECT_NEAR(at_truth.EffectValues(k, exact.x)[0], expected, 1e-6) << k;
  }
  const JointNormalEquations eq = AccumulateNormalEquations(c.model, train);
  const JointIdentificationResult held = IdentifyJointModel(c.model, eq, options);
  EXPECT_EQ(held.x.head(30).cwiseAbs().maxCoeff(), 0.0);
  options.frozen_bodies = {false, true, false};
  const JointIdentificationResult one = IdentifyJointModel(c.model, eq, options);
  EXPECT_EQ(one.x.segment<10>(10).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_GT(one.x.head(10).cwiseAbs().maxCoeff(), 1e-3);
  const JointIdentificationResult free = IdentifyJointModel(c.model, eq);
  EXPECT_LT(free.data_cost, one.data_cost);
  EXPECT_LT(one.data_cost, held.data_cost);
  options.frozen_bodies = {true};
  EXPECT_THROW(IdentifyJointModel(c.model, eq, options), std::invalid_argument);
}

// The prior without effects predicts the links' torques alone.
TEST(JointIdentification, PriorWithoutEffectsIsTheLinksAlone) {
  Rng rng(35);
  const Case c = MakeCase("viscous,coulomb:scale=0.05,offset,spring");
  const RobotDynamics links(Leg(PriorLinks()), kJoints, {}, NoLinks());
  const JointSamples data = ExciteLeg(c.truth, c.x_true, 50, 0.01, 0.0, rng, 0.0);
  const Eigen::MatrixXd with = PredictJointTorques(c.model, PriorParametersWithoutEffects(c.model), data);
  const Eigen::MatrixXd alone = PredictJointTorques(links, Eigen::VectorXd::Zero(links.num_parameters()), data);
  EXPECT_LT((with - alone).cwiseAbs().maxCoeff(), 1e-12 * alone.cwiseAbs().maxCoeff());
}

}  // namespace
}  // namespace inertial
