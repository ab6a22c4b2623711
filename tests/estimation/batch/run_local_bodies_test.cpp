// A body present in one run only (run_local_bodies.hpp). The own block against its link's columns
// and the masked statistics against an explicit sum over samples (the algebra, independently of
// any fit); then the leg simulated in two runs, the second carrying a 2 kg box (a closed-form
// SolidBox) on the shank: from both runs at 0.05 N m of noise, the box's COM within 5 mm with its
// mass stated (held exactly) and its mass within 2 % when not; and every joint logged with an
// unknown gain, where the stated mass alone fixes the torque scale (to within the regularizer's
// pull: 2 % at the paper's weight with links 25 % off their URDF, 0.4 % at a tenth of it).
#include "inertial/estimation/batch/run_local_bodies.hpp"

#include <gtest/gtest.h>

#include "estimation/leg_chain.hpp"
#include "inertial/inertia/closed_form_bodies.hpp"
#include "inertial/model/body_torques.hpp"
#include "simulated_robot.hpp"

namespace inertial {
namespace {

const InertialParams kBox = SolidBox(2.0, 0.08, 0.06, 0.15, Pose{Matrix3::Identity(), Vector3(0.02, -0.01, -0.12)});

bool Shank(const std::string& link, LinkLocation* at) {
  if (link != "shank") return false;
  at->body = 2;
  return true;
}

// The leg with a payload on the shank: the box itself (shared columns), or a prior of `mass` at the
// shank's origin with a block of its own (or, shared_prior, the same prior in the shank's columns).
RobotDynamics Leg(bool own, double mass = 2.0, bool shared_prior = false) {
  std::vector<EffectSpec> effects = ParseEffectList("payload@shank");
  effects[0].inertia = own || shared_prior ? SolidSphere(mass, 0.05) : kBox;
  effects[0].own_features = own;
  return RobotDynamics(testing::LegChain(testing::LegPriorLinks()), testing::kLegJoints, effects, Shank);
}

struct TwoRuns {
  RobotDynamics links = RobotDynamics(testing::LegChain(testing::LegPriorLinks()), testing::kLegJoints, {}, testing::NoLinks());
  Eigen::VectorXd x_links;
  std::vector<JointSamples> runs;  // without, with the box
  JointSamples held_out;           // the links alone, another trajectory, without noise
};

const TwoRuns& Runs() {
  static const TwoRuns r = [] {
    TwoRuns t;
    const RobotDynamics loaded = Leg(false);
    Eigen::VectorXd x = testing::TrueParameters(loaded, {0.0}, 39);
    x.segment<10>(30).setZero();  // the box as it is
    t.x_links = x.head(30);
    const testing::SimulatedLogs a = testing::SimulateLogs(t.links, t.x_links, 0.05, 12.0, 3, 200);
    t.runs = {a.train, testing::SimulateLogs(loaded, x, 0.05, 12.0, 4, 200).train};
    t.held_out = a.test_clean;
    return t;
  }();
  return r;
}

TEST(RunLocalBodies, AnOwnBlockRepeatsItsLinksColumnsAndMovesWithIt) {
  const RobotDynamics own = Leg(true), shared = Leg(false, 2.0, true);
  ASSERT_EQ(own.num_features(), shared.num_features() + 10);
  EXPECT_EQ(own.bodies()[3].block, 3);
  EXPECT_EQ(own.bodies()[3].tree_body, 2);
  testing::Rng rng(7);
  Eigen::MatrixXd A(3, own.num_features());
  for (int trial = 0; trial < 5; ++trial) {
    Eigen::VectorXd q(3), qd(3), qdd(3), x(own.num_parameters());
    for (int j = 0; j < 3; ++j) q[j] = rng.Uniform(-1, 1), qd[j] = rng.Uniform(-2, 2), qdd[j] = rng.Uniform(-5, 5);
    for (int i = 0; i < x.size(); ++i) x[i] = rng.Uniform(-0.3, 0.3);
    own.Features(q, qd, qdd, A);
    EXPECT_EQ((A.middleCols<10>(30) - A.middleCols<10>(20)).norm(), 0.0);
    // Newton-Euler on the bodies (the payload added to the shank) against the regressor.
    const Eigen::VectorXd tau = own.InverseDynamics(x, q, qd, qdd);
    EXPECT_LT((tau - A * own.Coefficients(x)).norm(), 1e-10 * tau.norm()) << trial;
    // The same bodies with the payload in its link's columns.
    EXPECT_LT((tau - shared.InverseDynamics(x, q, qd, qdd)).norm(), 1e-10 * tau.norm()) << trial;
  }
}

TEST(RunLocalBodies, StatisticsAreThoseOfTheRegressorZeroedOutsideTheRun) {
  const RobotDynamics m = Leg(true);
  const TwoRuns& r = Runs();
  const JointNormalEquations s = AccumulateRunNormalEquations(m, r.runs, {-1, -1, -1, 1});
  Eigen::MatrixXd AtA = Eigen::MatrixXd::Zero(m.num_features(), m.num_features()), A(3, m.num_features());
  Eigen::VectorXd Atb = Eigen::VectorXd::Zero(m.num_features());
  double btb = 0.0;
  for (int k = 0; k < 2; ++k) {
    const JointSamples& d = r.runs[static_cast<size_t>(k)];
    for (int i = 0; i < d.size(); ++i) {
      m.Features(d.q.row(i).transpose(), d.qd.row(i).transpose(), d.qdd.row(i).transpose(), A);
      if (k == 0) A.middleCols<10>(30).setZero();
      AtA += A.transpose() * A;
      Atb += A.transpose() * d.tau.row(i).transpose();
      btb += d.tau.row(i).squaredNorm();
    }
  }
  EXPECT_LT((s.AtA - AtA).norm(), 1e-11 * AtA.norm());
  EXPECT_LT((s.Atb - Atb).norm(), 1e-11 * Atb.norm());
  EXPECT_NEAR(s.btb, btb, 1e-11 * btb);
  EXPECT_EQ(s.num_samples, r.runs[0].size() + r.runs[1].size());
  EXPECT_THROW(AccumulateRunNormalEquations(m, r.runs, {-1, 0, -1, 1}), std::invalid_argument);  // a link
  EXPECT_THROW(AccumulateRunNormalEquations(m, r.runs, {-1, -1, -1, 2}), std::invalid_argument);  // no run 2
  EXPECT_THROW(AccumulateRunNormalEquations(m, r.runs, {-1, -1, 1}), std::invalid_argument);      // size
}

// The fitted box against the closed-form one, and the links against their truth on a held-out
// trajectory (noise-free torques of the links alone).
void ExpectTheBox(const RobotDynamics& m, const JointIdentificationResult& fit, double mass_tolerance) {
  const InertialParams box = m.BodyInertia(3, fit.x);
  std::cerr << "box: mass " << box.mass() << " kg, COM error " << 1e3 * (box.com() - kBox.com()).norm() << " mm\n";
  EXPECT_NEAR(box.mass(), kBox.mass(), mass_tolerance * kBox.mass());
  EXPECT_LT((box.com() - kBox.com()).norm(), 5e-3);
  const TwoRuns& r = Runs();
  Eigen::VectorXd x_links = fit.x.head(30);
  const Eigen::MatrixXd predicted = PredictJointTorques(r.links, x_links, r.held_out);
  const TorqueErrors e = CompareTorques(predicted, r.held_out.tau);
  EXPECT_LT(e.total_rms, 0.05) << "the links' error on held-out torques, below the training noise";
}

TEST(RunLocalBodies, AStatedMassIsHeldAndTheComFoundFromTwoRuns) {
  const RobotDynamics m = Leg(true, 2.0);
  JointIdentificationOptions o;
  o.held_parameters = {30};  // the box's alpha
  const JointIdentificationResult fit = IdentifyJointModel(m, AccumulateRunNormalEquations(m, Runs().runs, {-1, -1, -1, 1}), o);
  EXPECT_EQ(fit.x[30], 0.0);
  EXPECT_NEAR(m.BodyInertia(3, fit.x).mass(), 2.0, 1e-12);
  ExpectTheBox(m, fit, 1e-12);
}

TEST(RunLocalBodies, AnUnknownPayloadIsFoundFromTwoRuns) {
  const RobotDynamics m = Leg(true, 0.5);
  const JointIdentificationResult fit = IdentifyJointModel(m, AccumulateRunNormalEquations(m, Runs().runs, {-1, -1, -1, 1}));
  ExpectTheBox(m, fit, 0.02);
}

TEST(RunLocalBodies, WithEveryJointLoggedWithAGainTheStatedMassFixesTheScale) {
  const RobotDynamics m = Leg(true, 2.0);
  const Eigen::Vector3d gains(8.0, 11.5, 15.0);
  std::vector<JointSamples> logged = Runs().runs;
  for (JointSamples& d : logged) d.tau = d.tau * gains.asDiagonal();
  const std::vector<Eigen::MatrixXd> none(2);
  const std::vector<int> dofs{0, 1, 2};
  JointIdentificationOptions o;
  EXPECT_TRUE(GainScaleProblem(m, Eigen::MatrixXd(), dofs, {}, o.held_parameters).has_value());
  o.held_parameters = {30};
  EXPECT_FALSE(GainScaleProblem(m, Eigen::MatrixXd(), dofs, {}, o.held_parameters).has_value());
  const GainIdentificationResult r = IdentifyWithGains(m, AccumulateRunGainProblem(m, logged, none, dofs, {-1, -1, -1, 1}), o);
  // Measured (seed 39, 0.05 N m): 8.035, 11.611, 15.303 (+0.4, +1.0, +2.0 %). A bias of the
  // regularizer, as with a known COM (gain_identification.hpp) but larger, since only the box's mass
  // column is known in N m: with the prior weight 1e-3 the gains come out +0.1, +0.3, +0.4 %, with
  // 1e-4 +0.08, +0.17, +0.18 %. Moving the box's prior to its fitted COM and fitting again changes
  // them by less than 0.1 %, so the pull is on the links' scale (25 % off their URDF here), not on
  // the box. Bound: 2.5 % at the paper's weight; 0.5 % at 1e-3.
  for (int j = 0; j < 3; ++j) {
    std::cerr << "gain " << j << ": " << r.gains[j] << " (true " << gains[j] << ")\n";
    EXPECT_NEAR(r.gains[j] / gains[j], 1.0, 0.025) << j;
  }
  o.prior_weight = 1e-3;
  const GainIdentificationResult weak =
      IdentifyWithGains(m, AccumulateRunGainProblem(m, logged, none, dofs, {-1, -1, -1, 1}), o);
  for (int j = 0; j < 3; ++j) EXPECT_NEAR(weak.gains[j] / gains[j], 1.0, 0.005) << j;
  EXPECT_NEAR(m.BodyInertia(3, r.fit.x).mass(), 2.0, 1e-12);
}

// The gain problem's statistics (gain_identification.hpp) of two runs, the knee logged with a gain
// and the box's block zeroed in the first run, against sums over the samples.
TEST(RunLocalBodies, GainStatisticsAreThoseOfTheRegressorZeroedOutsideTheRun) {
  const RobotDynamics m = Leg(true);
  const TwoRuns& r = Runs();
  std::vector<Eigen::MatrixXd> known;
  for (const JointSamples& d : r.runs) known.push_back(0.1 * d.tau);  // any known torque
  const GainProblem p = AccumulateRunGainProblem(m, r.runs, known, {2}, {-1, -1, -1, 1});
  const int F = m.num_features();
  Eigen::MatrixXd AtA = Eigen::MatrixXd::Zero(F, F), A(3, F);
  Eigen::VectorXd Atb = Eigen::VectorXd::Zero(F), Aty = Eigen::VectorXd::Zero(F), Atp = Eigen::VectorXd::Zero(F);
  double yty = 0.0;
  for (int k = 0; k < 2; ++k) {
    const JointSamples& d = r.runs[static_cast<size_t>(k)];
    for (int i = 0; i < d.size(); ++i) {
      m.Features(d.q.row(i).transpose(), d.qd.row(i).transpose(), d.qdd.row(i).transpose(), A);
      if (k == 0) A.middleCols<10>(30).setZero();
      Eigen::Vector3d b = d.tau.row(i).transpose() - known[static_cast<size_t>(k)].row(i).transpose();
      b[2] = -known[static_cast<size_t>(k)](i, 2);  // the gain joint's b: minus the known torque
      AtA += A.transpose() * A;
      Atb += A.transpose() * b;
      Aty += A.row(2).transpose() * d.tau(i, 2);
      Atp += A.row(2).transpose() * known[static_cast<size_t>(k)](i, 2);
      yty += d.tau(i, 2) * d.tau(i, 2);
    }
  }
  EXPECT_LT((p.links.AtA - AtA).norm(), 1e-11 * AtA.norm());
  EXPECT_LT((p.links.Atb - Atb).norm(), 1e-11 * Atb.norm());
  EXPECT_LT((p.Aty[0] - Aty).norm(), 1e-11 * Aty.norm());
  EXPECT_LT((p.known[2].Atb - Atp).norm(), 1e-11 * Atp.norm());
  EXPECT_NEAR(p.yty[0], yty, 1e-11 * yty);
  EXPECT_EQ(p.Aty[0].segment<10>(30).norm() > 0.0, true);  // the box's run is in it
}

}  // namespace
}  // namespace inertial
