// The online estimators on simulated streams of the bundled robots (examples/leg3.urdf with
// rotors and friction: 66 parameters; examples/arm7.urdf with friction: 84): recursive
// Gauss-Newton from the URDF priors converges to the true robot's torques (judged on a fresh
// noise-free trajectory, the identifiable combinations) with every body of every tick fully
// consistent; the gradient law improves on the prior; faults leave the estimate finite,
// consistent and, after the burst, as good as a clean run's.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <memory>
#include <limits>

#include "inertial/estimation/batch/joint_identification.hpp"
#include "inertial/estimation/online/online_joint_estimator.hpp"
#include "inertial/inertia/consistency.hpp"
#include "inertial/formats/model_file.hpp"
#include "simulated_robot.hpp"

namespace inertial {
namespace {

JointSample At(const JointSamples& s, int k) {
  return JointSample{s.t[k], s.q.row(k).transpose(), s.qd.row(k).transpose(), s.qdd.row(k).transpose(),
                     s.tau.row(k).transpose()};
}

// RMS torque error of the estimator's current coefficients on a log.
double RmsError(const OnlineJointEstimator& est, const JointSamples& log) {
  const RobotDynamics& model = est.model();
  Eigen::MatrixXd A(model.num_dofs(), model.num_features());
  double sum = 0;
  for (int k = 0; k < log.size(); ++k) {
    model.Features(log.q.row(k).transpose(), log.qd.row(k).transpose(), log.qdd.row(k).transpose(), A);
    sum += (A * est.coefficients() - log.tau.row(k).transpose()).squaredNorm();
  }
  return std::sqrt(sum / (log.size() * model.num_dofs()));
}

int InconsistentBodies(const OnlineJointEstimator& est) {
  int bad = 0;
  for (int e = 0; e < static_cast<int>(est.model().bodies().size()); ++e) bad += !IsPhysicallyConsistent(est.Body(e));
  return bad;
}

struct Case {
  const char* urdf;
  const char* effects;
  std::vector<double> effect_values;
  double sigma;
};

const Case kLeg{"leg3.urdf", "viscous,coulomb:scale=0.05,rotor@abad:gear=6,rotor@hip:gear=6,rotor@knee:gear=9.33",
                {0.2, 0.2, 0.2, 0.5, 0.5, 0.5}, 0.3};
const Case kArm{"arm7.urdf", "viscous,coulomb:scale=0.05", {0.3, 0.3, 0.3, 0.3, 0.3, 0.3, 0.3, 0.8, 0.8, 0.8, 0.8, 0.8, 0.8, 0.8}, 0.3};

// The case's model and logs (40 s at 200 Hz of the robot perturbed from its priors), simulated
// once per case in a process.
struct Stream {
  RobotDynamics model;
  testing::SimulatedLogs logs;
};
const Stream& StreamOf(const Case& c) {
  static std::map<const Case*, std::unique_ptr<Stream>> cache;
  std::unique_ptr<Stream>& s = cache[&c];
  if (!s) {
    RobotDynamics model = MakeRobotDynamics(LoadUrdf(testing::Example(c.urdf)), ParseEffectList(c.effects));
    const Eigen::VectorXd x_true = testing::TrueParameters(model, c.effect_values, 3);
    testing::SimulatedLogs logs = testing::SimulateLogs(model, x_true, c.sigma, 40.0, 11, 200);
    s = std::make_unique<Stream>(Stream{std::move(model), std::move(logs)});
  }
  return *s;
}

// Recursive Gauss-Newton over 40 s at 200 Hz: the noise-free torques of an unseen trajectory are
// predicted to within 0.3 sigma (the batch fit on the same data reaches about 0.05 sigma: see
// robot_identification_test; the online estimate, one pass with early linearizations far from
// the truth, is allowed six times that), starting from a prior 10 sigma off.
void ExpectGaussNewtonConverges(const Case& c) {
  const Stream& stream = StreamOf(c);
  const RobotDynamics& model = stream.model;
  const testing::SimulatedLogs& logs = stream.logs;
  OnlineEstimatorOptions o;
  o.kind = EstimatorKind::kEkf;  // the per-sample Kalman estimator (online_fit_test.cpp: the fit)
  o.measurement_sigma = c.sigma;
  OnlineJointEstimator est(model, Eigen::VectorXd::Zero(model.num_parameters()), o);
  const double prior_error = RmsError(est, logs.test_clean);
  int inconsistent_ticks = 0;
  for (int k = 0; k < logs.train.size(); ++k) {
    est.Update(At(logs.train, k));
    inconsistent_ticks += InconsistentBodies(est) > 0;
  }
  const double error = RmsError(est, logs.test_clean);
  std::cerr << c.urdf << ": " << model.num_parameters() << " parameters, clean-torque RMS prior " << prior_error
            << ", online " << error << " (sigma " << c.sigma << "); accepted " << est.estimator().counters().accepted()
            << " of " << logs.train.size() << "\n";
  EXPECT_EQ(inconsistent_ticks, 0);
  EXPECT_GT(prior_error, 3 * c.sigma);
  EXPECT_LT(error, 0.3 * c.sigma);
  EXPECT_GE(est.estimator().counters().accepted(), static_cast<std::uint64_t>(0.99 * logs.train.size()));

  // Seeded from a batch fit (eq. 14 on the first 10 s) instead of the priors: it starts where the
  // fit is (0.04 N m here) and stays within the same bound (it ends at 0.04 to 0.06 N m: with the
  // default initial uncertainty it does not know how good its seed is, and follows the noise a
  // little; a seed's covariance from the fit would keep it tighter).
  JointSamples first = logs.train;
  const int n10 = 2000;
  first.t = first.t.head(n10).eval();
  for (Eigen::MatrixXd* m : {&first.q, &first.qd, &first.qdd, &first.tau}) *m = m->topRows(n10).eval();
  const JointIdentificationResult fit = IdentifyJointModel(model, AccumulateNormalEquations(model, first));
  OnlineJointEstimator seeded(model, fit.x, o);
  const Eigen::VectorXd w_fit = model.Coefficients(fit.x);
  EXPECT_LT((seeded.coefficients() - w_fit).norm(), 1e-12 * w_fit.norm());
  const double seeded_start = RmsError(seeded, logs.test_clean);
  for (int k = n10; k < logs.train.size(); ++k) seeded.Update(At(logs.train, k));
  const double seeded_end = RmsError(seeded, logs.test_clean);
  std::cerr << "seeded from a 10 s batch fit: clean-torque RMS " << seeded_start << " -> " << seeded_end << "\n";
  EXPECT_LT(seeded_start, 0.2 * prior_error);
  EXPECT_LT(seeded_end, 0.3 * c.sigma);
}

TEST(OnlineRobotEstimation, GaussNewtonLegWithRotorsAndFriction) { ExpectGaussNewtonConverges(kLeg); }
TEST(OnlineRobotEstimation, GaussNewtonArmWithFriction) { ExpectGaussNewtonConverges(kArm); }

// The gradient law (no covariance, no solve; gradient_estimator.hpp) on the leg with rotors and
// friction (66 parameters, 40 s): every tick consistent, and its predictions of the held-out clean
// torques at least 5 times better than the prior's (the bound leaves room for another machine's
// rounding, below). Measured: prior 3.17 N m, the law 0.078 or
// 0.211 (the matrix exponential by eigen-decomposition or by Taylor series: rounding alone moves
// it, along what the stream hardly excites, where the objective is flat and the law has no prior),
// the online fit of the same stream 0.017 (its solve holds those directions at the prior). On
// measured torques the law is within 1.1 times the batch fit (tools.GradientLaw). The law before
// (a normalized LMS) ended at 0.97 N m.
TEST(OnlineRobotEstimation, GradientLawImprovesOnThePrior) {
  const Stream& stream = StreamOf(kLeg);
  const RobotDynamics& model = stream.model;
  const testing::SimulatedLogs& logs = stream.logs;
  OnlineEstimatorOptions o;
  o.kind = EstimatorKind::kGradient;
  o.measurement_sigma = kLeg.sigma;
  OnlineJointEstimator est(model, Eigen::VectorXd::Zero(model.num_parameters()), o);
  const double prior_error = RmsError(est, logs.test_clean);
  for (int k = 0; k < logs.train.size(); ++k) {
    est.Update(At(logs.train, k));
    ASSERT_EQ(InconsistentBodies(est), 0) << k;
  }
  const double error = RmsError(est, logs.test_clean);
  std::cerr << "gradient law on the leg: clean-torque RMS prior " << prior_error << ", law " << error << "\n";
  EXPECT_LT(error, prior_error / 5);
}

// Faults on the arm's stream: NaN/Inf in q, qd, qdd, tau and t; repeated and out-of-order time
// stamps; a burst of 50 samples with 100x-noise outliers on every joint at t = 20 s; 400 dropped
// samples. Every tick finite and consistent; the final error within 1.5 times the clean run's
// (plus 0.02 sigma).
TEST(OnlineRobotEstimation, FaultsOnTheArmStream) {
  const Stream& stream = StreamOf(kArm);
  const RobotDynamics& model = stream.model;
  const testing::SimulatedLogs& logs = stream.logs;
  OnlineEstimatorOptions o;
  o.kind = EstimatorKind::kEkf;  // the per-sample Kalman estimator (online_fit_test.cpp: the fit)
  o.measurement_sigma = kArm.sigma;
  OnlineJointEstimator clean(model, Eigen::VectorXd::Zero(model.num_parameters()), o);
  for (int k = 0; k < logs.train.size(); ++k) clean.Update(At(logs.train, k));
  const double clean_error = RmsError(clean, logs.test_clean);

  OnlineJointEstimator est(model, Eigen::VectorXd::Zero(model.num_parameters()), o);
  testing::Rng rng(5);
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  std::uint64_t non_finite = 0, out_of_order = 0;
  for (int k = 0; k < logs.train.size(); ++k) {
    if (k >= 6000 && k < 6400) continue;  // dropped
    JointSample s = At(logs.train, k);
    if (k % 89 == 3) {
      JointSample bad = s;
      const int j = (k / 89) % 7;
      switch ((k / 89) % 5) {
        case 0: bad.q[j] = nan; break;
        case 1: bad.qd[j] = inf; break;
        case 2: bad.qdd[j] = -inf; break;
        case 3: bad.tau[j] = nan; break;
        case 4: bad.t = inf; break;
      }
      const Eigen::VectorXd before = est.estimator().parameters();
      EXPECT_EQ(est.Update(bad), UpdateStatus::kNonFinite);
      EXPECT_EQ(est.estimator().parameters(), before);
      ++non_finite;
    }
    if (k % 97 == 11 && k > 0) {
      JointSample old = At(logs.train, k - 1);
      EXPECT_EQ(est.Update(old), UpdateStatus::kOutOfOrder);
      old.t -= 1.0;
      EXPECT_EQ(est.Update(old), UpdateStatus::kOutOfOrder);
      out_of_order += 2;
    }
    if (k >= 4000 && k < 4050) {
      for (int j = 0; j < 7; ++j) s.tau[j] += 100 * kArm.sigma * (rng.Uniform(0, 1) < 0.5 ? -1 : 1);
    }
    est.Update(s);
    ASSERT_TRUE(est.estimator().parameters().allFinite()) << k;
    ASSERT_EQ(InconsistentBodies(est), 0) << k;
  }
  const UpdateCounters& c = est.estimator().counters();
  EXPECT_EQ(c[UpdateStatus::kNonFinite], non_finite);
  EXPECT_EQ(c[UpdateStatus::kOutOfOrder], out_of_order);
  EXPECT_GE(c[UpdateStatus::kOutlier], 45u);
  const double error = RmsError(est, logs.test_clean);
  std::cerr << "arm with faults: clean-torque RMS " << error << " (clean run " << clean_error << ")\n";
  EXPECT_LT(error, 1.5 * clean_error + 0.02 * kArm.sigma);
}

}  // namespace
}  // namespace inertial
