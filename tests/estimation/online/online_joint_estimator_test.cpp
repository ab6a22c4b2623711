// The online robot estimator (online_joint_estimator.hpp) on the leg chain: estimator names; one
// sample copied out of a log; the start at x0 = 0 is the priors' bodies (the closed-form boxes and
// cylinder); predicted and residual are those of the coefficients before the sample (the links'
// inverse dynamics plus the friction, summed here); on exact torques of the true leg every kind
// predicts a fresh trajectory's torques (computed by the true model) better than the prior, and
// linear RLS is the batch regularized least squares solved here; bad samples are rejected,
// counted, and change nothing; bad sizes throw.
#include "inertial/estimation/online/online_joint_estimator.hpp"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>

#include <cmath>
#include <limits>
#include <stdexcept>

#include "estimation/leg_chain.hpp"
#include "simulated_robot.hpp"
#include "test_support.hpp"

namespace inertial {
namespace {

RobotDynamics PriorLeg(const std::string& effects = "") {
  return RobotDynamics(testing::LegChain(testing::LegPriorLinks()), testing::kLegJoints, ParseEffectList(effects),
                       testing::NoLinks());
}

// RMS over a log of (torques predicted by coefficients w) - (log's torques).
double TorqueRms(const RobotDynamics& model, const Eigen::VectorXd& w, const JointSamples& log) {
  double s = 0.0;
  for (int i = 0; i < log.size(); ++i) {
    const Eigen::VectorXd tau = model.InverseDynamicsFromCoefficients(w, log.q.row(i).transpose(),
                                                                      log.qd.row(i).transpose(), log.qdd.row(i).transpose());
    s += (tau - log.tau.row(i).transpose()).squaredNorm();
  }
  return std::sqrt(s / (log.size() * log.tau.cols()));
}

TEST(OnlineJointEstimator, EstimatorNames) {
  for (EstimatorKind k : {EstimatorKind::kGaussNewton, EstimatorKind::kEkf, EstimatorKind::kGradient, EstimatorKind::kLinearRls}) {
    EXPECT_EQ(ParseEstimatorKind(ToString(k)), k);
  }
  EXPECT_EQ(ToString(EstimatorKind::kGaussNewton), "gauss_newton");
  EXPECT_EQ(ToString(EstimatorKind::kLinearRls), "linear_rls");
  EXPECT_THROW(ParseEstimatorKind("kalman"), std::invalid_argument);
}

TEST(OnlineJointEstimator, CopySampleTakesOneRow) {
  JointSamples log;
  log.t = Eigen::Vector2d(0.5, 0.75);
  log.q = Eigen::Matrix<double, 2, 3>::Constant(1.0);
  log.qd = Eigen::Matrix<double, 2, 3>::Constant(2.0);
  log.qdd = Eigen::Matrix<double, 2, 3>::Constant(3.0);
  log.tau = Eigen::Matrix<double, 2, 3>::Constant(4.0);
  log.q(1, 2) = -7.0;
  log.tau(1, 0) = 9.0;
  JointSample s;
  s.has_qdd = false;
  CopySample(log, 1, &s);
  EXPECT_EQ(s.t, 0.75);
  EXPECT_EQ(s.q, Eigen::Vector3d(1, 1, -7));
  EXPECT_EQ(s.qd, Eigen::Vector3d::Constant(2));
  EXPECT_EQ(s.qdd, Eigen::Vector3d::Constant(3));
  EXPECT_EQ(s.tau, Eigen::Vector3d(9, 4, 4));
  EXPECT_TRUE(s.has_qdd);
}

TEST(OnlineJointEstimator, StartsAtThePriorsAndPredictsBeforeTheUpdate) {
  const RobotDynamics model = PriorLeg("viscous");
  const std::vector<InertialParams> priors = testing::LegPriorLinks();
  for (EstimatorKind kind : {EstimatorKind::kGaussNewton, EstimatorKind::kEkf, EstimatorKind::kGradient, EstimatorKind::kLinearRls}) {
    OnlineEstimatorOptions o;
    o.kind = kind;
    OnlineJointEstimator est(model, Eigen::VectorXd::Zero(model.num_parameters()), o);
    EXPECT_EQ(est.kind(), kind);
    for (int e = 0; e < 3; ++e) {
      EXPECT_LT((est.Body(e).vector() - priors[e].vector()).norm(), 1e-12 * priors[e].vector().norm()) << e;
    }
    EXPECT_EQ(est.predicted(), Eigen::Vector3d::Zero());
    EXPECT_EQ(est.residual(), Eigen::Vector3d::Zero());
    // One sample: predicted is the prior's torque, the links' inverse dynamics at the priors plus
    // viscous friction b qd with b = e^0 = 1 (x = 0), summed here; residual = tau - predicted.
    JointSample s;
    s.t = 0.1;
    s.q = Eigen::Vector3d(0.1, -0.4, 0.8);
    s.qd = Eigen::Vector3d(0.5, 0.2, -1.0);
    s.qdd = Eigen::Vector3d(1.0, -2.0, 0.5);
    s.tau = Eigen::Vector3d(1.0, 2.0, 3.0);
    const RobotDynamics links = PriorLeg();
    const Eigen::VectorXd tau0 =
        links.InverseDynamics(Eigen::VectorXd::Zero(links.num_parameters()), s.q, s.qd, s.qdd) + s.qd;
    // The fit holds its first samples (buffered) until its first solve, which runs off the tick.
    ASSERT_EQ(est.Update(s), kind == EstimatorKind::kGaussNewton ? UpdateStatus::kBuffered : UpdateStatus::kAccepted);
    EXPECT_EQ(est.Solve(), kind == EstimatorKind::kGaussNewton);
    EXPECT_LT((est.predicted() - tau0).norm(), 1e-12 * tau0.norm()) << ToString(kind);
    EXPECT_LT((est.residual() - (s.tau - tau0)).norm(), 1e-12 * tau0.norm());
    EXPECT_NE(est.coefficients(), model.Coefficients(Eigen::VectorXd::Zero(model.num_parameters())));
  }
}

// Exact torques of the true leg (links 25 % off the priors) over 20 s at 100 Hz. Linear RLS is the
// batch regularized least squares (P0^-1 + A^T A / s^2)^-1 (P0^-1 w0 + A^T tau / s^2), solved here
// on the stacked features; every kind, judged on an unseen trajectory's torques computed by the
// true model, improves on the prior.
TEST(OnlineJointEstimator, EachKindLearnsTheTrueLeg) {
  const RobotDynamics model = PriorLeg();
  const Eigen::VectorXd x_true = testing::TrueParameters(model, {0.0}, 3, 0.25);
  const testing::SimulatedLogs logs = testing::SimulateLogs(model, x_true, 0.0, 20.0, 3, 100);
  const Eigen::VectorXd w0 = model.Coefficients(Eigen::VectorXd::Zero(model.num_parameters()));
  const double prior_rms = TorqueRms(model, w0, logs.test_clean);
  ASSERT_GT(prior_rms, 0.05);
  const double inf = std::numeric_limits<double>::infinity();
  for (EstimatorKind kind : {EstimatorKind::kGaussNewton, EstimatorKind::kEkf, EstimatorKind::kGradient, EstimatorKind::kLinearRls}) {
    OnlineEstimatorOptions o;
    o.kind = kind;
    if (kind != EstimatorKind::kGradient) {
      o.measurement_sigma = 0.05;
      o.kalman.huber = o.kalman.gate = inf;  // the prior's errors are tens of sigmas: no down-weighting
    }
    OnlineJointEstimator est(model, Eigen::VectorXd::Zero(model.num_parameters()), o);
    JointSample s;
    for (int i = 0; i < logs.train.size(); ++i) {
      CopySample(logs.train, i, &s);
      est.Update(s);
      if (est.SolveDue()) est.Solve();
    }
    est.Solve();
    const double rms = TorqueRms(model, est.coefficients(), logs.test_clean);
    if (kind == EstimatorKind::kGradient) {
      EXPECT_LT(rms, 0.3 * prior_rms);
      continue;
    }
    EXPECT_EQ(est.estimator().counters().accepted(), static_cast<std::uint64_t>(logs.train.size())) << ToString(kind);
    EXPECT_LT(rms, 0.05 * prior_rms) << ToString(kind);
    if (kind == EstimatorKind::kLinearRls) {
      const int F = model.num_features(), n = model.num_dofs();
      const Eigen::VectorXd std_w = 0.3 * (w0.cwiseAbs().array() + 0.01);
      Eigen::MatrixXd normal = std_w.array().square().inverse().matrix().asDiagonal();
      Eigen::VectorXd rhs = normal * w0;
      Eigen::MatrixXd A(n, F);
      const double s2 = o.measurement_sigma * o.measurement_sigma;
      for (int i = 0; i < logs.train.size(); ++i) {
        model.Features(logs.train.q.row(i).transpose(), logs.train.qd.row(i).transpose(),
                       logs.train.qdd.row(i).transpose(), A);
        normal += A.transpose() * A / s2;
        rhs += A.transpose() * logs.train.tau.row(i).transpose() / s2;
      }
      const Eigen::VectorXd batch = normal.ldlt().solve(rhs);
      EXPECT_LT((est.coefficients() - batch).norm(), 1e-6 * batch.norm());
    }
  }
}

TEST(OnlineJointEstimator, BadSamplesAreRejectedAndCounted) {
  const RobotDynamics model = PriorLeg();
  OnlineJointEstimator est(model, Eigen::VectorXd::Zero(model.num_parameters()));
  const Eigen::VectorXd w0 = est.coefficients();
  JointSample s;
  s.t = 0.0;
  s.q = s.qd = s.qdd = s.tau = Eigen::Vector3d(0.1, 0.2, 0.3);
  s.qd[1] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(est.Update(s), UpdateStatus::kNonFinite);
  s.qd[1] = 0.2;
  s.tau = Eigen::VectorXd::Ones(2);
  EXPECT_EQ(est.Update(s), UpdateStatus::kWrongSize);
  EXPECT_EQ(est.estimator().counters()[UpdateStatus::kNonFinite], 1u);
  EXPECT_EQ(est.estimator().counters()[UpdateStatus::kWrongSize], 1u);
  EXPECT_EQ(est.estimator().counters().accepted(), 0u);
  EXPECT_EQ(est.coefficients(), w0);

  EXPECT_THROW(OnlineJointEstimator(model, Eigen::VectorXd::Zero(model.num_parameters() + 1)), std::invalid_argument);
  OnlineEstimatorOptions o;
  o.kind = EstimatorKind::kEkf;
  o.initial_std = Eigen::VectorXd::Ones(3);
  EXPECT_THROW(OnlineJointEstimator(model, Eigen::VectorXd::Zero(model.num_parameters()), o), std::invalid_argument);
}

}  // namespace
}  // namespace inertial

namespace inertial {
namespace {

// A restored state is the adapter's at once: coefficients(), Body() and the next sample's prediction
// are those of the restored parameters (w(x) recomputed here by RobotDynamics::Coefficients, or x
// itself for linear RLS), not the priors the adapter started from.
TEST(OnlineJointEstimator, RestoreTakesTheCoefficientsAtOnce) {
  const RobotDynamics model = PriorLeg("viscous");
  const Eigen::VectorXd x_true = testing::TrueParameters(model, {0.5}, 11, 0.2);
  const testing::SimulatedLogs logs = testing::SimulateLogs(model, x_true, 0.0, 4.0, 11, 100);
  for (EstimatorKind kind : {EstimatorKind::kGaussNewton, EstimatorKind::kEkf, EstimatorKind::kGradient, EstimatorKind::kLinearRls}) {
    OnlineEstimatorOptions o;
    o.kind = kind;
    OnlineJointEstimator learned(model, Eigen::VectorXd::Zero(model.num_parameters()), o);
    JointSample s;
    for (int i = 0; i + 1 < logs.train.size(); ++i) {
      CopySample(logs.train, i, &s);
      learned.Update(s);
    }
    OnlineJointEstimator restored(model, Eigen::VectorXd::Zero(model.num_parameters()), o);
    std::string why;
    ASSERT_TRUE(restored.Restore(learned.estimator().State(), &why)) << why;
    const Eigen::VectorXd& x = learned.estimator().parameters();
    const Eigen::VectorXd w = kind == EstimatorKind::kLinearRls ? x : model.Coefficients(x);
    EXPECT_LT((restored.coefficients() - w).norm(), 1e-12 * w.norm()) << ToString(kind);
    EXPECT_EQ(restored.Body(2).vector(), learned.Body(2).vector()) << ToString(kind);
    CopySample(logs.train, logs.train.size() - 1, &s);
    restored.Update(s);
    const Eigen::VectorXd expected = model.InverseDynamicsFromCoefficients(w, s.q, s.qd, s.qdd);
    EXPECT_LT((restored.predicted() - expected).norm(), 1e-9 * expected.norm()) << ToString(kind);
  }
}

}  // namespace
}  // namespace inertial
