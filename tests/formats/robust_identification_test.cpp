// Identification of the bundled leg (examples/leg3.urdf with rotors and friction, 66 parameters)
// from 20 s logs at 500 Hz (10001 rows) of the true robot along Fourier excitations, with glitched
// samples: IdentifyJointModelRobust (estimation/outlier_rejection.hpp) rejects exactly the glitched
// rows and predicts a trajectory it never saw as well as the fit of the clean log, where the plain
// fit is ruined or overflows. Seen: held-out RMS ratio to the clean fit 0.996 with one 1e6 N m
// torque (plain fit: 5484), 0.97 with a burst of 20 saturated rows (plain fit: 45).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>

#include "inertial/estimation/batch/robust_identification.hpp"
#include "inertial/formats/model_file.hpp"
#include "simulated_robot.hpp"

namespace inertial {
namespace {

using testing::Example;

constexpr double kSigma = 0.3;  // torque noise [N m]

bool Contains(const std::string& text, const std::string& fragment) { return text.find(fragment) != std::string::npos; }

/// The leg, its true parameters, a noise-free and a noisy training log and a noise-free test log
/// of another trajectory; simulated once for all tests.
struct Leg {
  RobotDynamics model;
  Eigen::VectorXd x_true;
  JointSamples train_exact, train, test_clean;
  double clean_rms = 0.0;  // held-out RMS of the plain fit of the clean noisy log [N m]
  int knee = -1, hip = -1;
};

const Leg& TheLeg() {
  static const std::unique_ptr<Leg> leg = [] {
    const RobotModel robot = LoadUrdf(Example("leg3.urdf"));
    RobotDynamics model = MakeRobotDynamics(
        robot, ParseEffectList("viscous,coulomb:scale=0.05,rotor@abad:gear=6,rotor@hip:gear=6,rotor@knee:gear=9.33"));
    const Eigen::VectorXd x_true = testing::TrueParameters(model, {0.2, 0.2, 0.2, 0.5, 0.5, 0.5}, 3);
    // The torques of the true robot along two Fourier excitations (inverse dynamics: exact, and
    // fast; robot_identification_test.cpp fits forward-simulated logs).
    const JointDynamicsFn id = [&](const Eigen::VectorXd& q, const Eigen::VectorXd& qd, const Eigen::VectorXd& qdd) {
      return model.InverseDynamics(x_true, q, qd, qdd);
    };
    JointSimulationOptions options;
    options.duration = 20.0;
    options.sample_rate_hz = 500.0;
    const FourierTrajectory train_ref = RandomFourierTrajectory(model.num_dofs(), 5, 0.1, 0.9, 11);
    const FourierTrajectory test_ref = RandomFourierTrajectory(model.num_dofs(), 5, 0.1, 0.9, 12);
    JointSamples train = SampleTrajectory(id, [&](double t) { return train_ref.Evaluate(t); }, options, model.dof_names());
    JointSamples test = SampleTrajectory(id, [&](double t) { return test_ref.Evaluate(t); }, options, model.dof_names());
    auto l = std::make_unique<Leg>(Leg{std::move(model), x_true, std::move(train), JointSamples(), std::move(test)});
    l->train = AddGaussianNoise(l->train_exact, SampleNoise{0, 0, 0, kSigma}, 13);
    const JointIdentificationResult fit = IdentifyJointModel(l->model, AccumulateNormalEquations(l->model, l->train));
    l->clean_rms = CompareTorques(PredictJointTorques(l->model, fit.x, l->test_clean), l->test_clean.tau).total_rms;
    for (int j = 0; j < l->model.num_dofs(); ++j) {
      if (l->model.dof_names()[j] == "knee") l->knee = j;
      if (l->model.dof_names()[j] == "hip") l->hip = j;
    }
    return l;
  }();
  return *leg;
}

double HeldOutRms(const Leg& leg, const Eigen::VectorXd& x) {
  return CompareTorques(PredictJointTorques(leg.model, x, leg.test_clean), leg.test_clean.tau).total_rms;
}

std::string FirstReason(const OutlierReport& r) { return r.reasons.empty() ? "" : r.reasons[0]; }

TEST(RobustIdentification, TheLegLogsHaveTheAdvertisedSize) {
  const Leg& leg = TheLeg();
  EXPECT_EQ(leg.train.size(), 10001);
  EXPECT_EQ(leg.model.num_parameters(), 66);
  ASSERT_GE(leg.knee, 0);
  ASSERT_GE(leg.hip, 0);
}

// Noise-free and Gaussian-noise logs: no row is rejected, and the result is the plain fit.
TEST(RobustIdentification, CleanLogsLoseNoRow) {
  const Leg& leg = TheLeg();
  for (const JointSamples* train : {&leg.train_exact, &leg.train}) {
    const RobustIdentificationResult r = IdentifyJointModelRobust(leg.model, *train, JointIdentificationOptions());
    EXPECT_TRUE(r.outliers.rejected.empty()) << r.outliers.rejected.size() << " rejected; the first: " << FirstReason(r.outliers);
    EXPECT_TRUE(r.outliers.settled);
    EXPECT_NEAR(r.outliers.threshold, 14.52, 0.01);  // 30003 residuals: ln(100 n) / (1.4826 ln 2)
    EXPECT_TRUE(r.fit.lm.converged()) << ToString(r.fit.lm.reason);
    EXPECT_EQ(r.fit.x, IdentifyJointModel(leg.model, AccumulateNormalEquations(leg.model, *train)).x);
  }
}

// One torque of 1e6 N m among 10001 rows: that row alone goes, and the held-out error is the clean
// fit's (the plain fit's is thousands of times worse).
TEST(RobustIdentification, OneGlitchedTorqueIsRejectedAlone) {
  const Leg& leg = TheLeg();
  JointSamples train = leg.train;
  train.tau(5000, leg.knee) = 1e6;
  const RobustIdentificationResult r = IdentifyJointModelRobust(leg.model, train, JointIdentificationOptions());
  EXPECT_EQ(r.outliers.rejected, std::vector<int>{5000}) << FirstReason(r.outliers);
  ASSERT_FALSE(r.outliers.reasons.empty());
  EXPECT_TRUE(Contains(r.outliers.reasons[0], "sample 5000 (t = 10 s): residual of the fit on knee -1e+06")) << r.outliers.reasons[0];
  EXPECT_TRUE(r.fit.lm.converged()) << ToString(r.fit.lm.reason);
  const double robust_rms = HeldOutRms(leg, r.fit.x);
  const double plain_rms = HeldOutRms(leg, IdentifyJointModel(leg.model, AccumulateNormalEquations(leg.model, train)).x);
  std::cerr << "held-out RMS: clean fit " << leg.clean_rms << " N m, robust " << robust_rms << " (ratio "
            << robust_rms / leg.clean_rms << "), plain " << plain_rms << " (ratio " << plain_rms / leg.clean_rms << ")\n";
  EXPECT_LT(robust_rms, 1.2 * leg.clean_rms);
  EXPECT_GT(plain_rms, 100.0 * leg.clean_rms) << "the glitch must ruin the plain fit, or this test proves nothing";
}

// tau = 1e300 and qd = 1e300 overflow the normal equations of the plain fit; the robust fit rejects
// both rows and converges.
TEST(RobustIdentification, OverflowingRowsAreRejectedAndTheFitIsFinite) {
  const Leg& leg = TheLeg();
  JointSamples train = leg.train;
  train.tau(3000, leg.knee) = 1e300;
  train.qd(7000, leg.hip) = 1e300;
  EXPECT_FALSE(std::isfinite(AccumulateNormalEquations(leg.model, train).btb));
  const RobustIdentificationResult r = IdentifyJointModelRobust(leg.model, train, JointIdentificationOptions());
  EXPECT_EQ(r.outliers.rejected, (std::vector<int>{3000, 7000})) << FirstReason(r.outliers);
  EXPECT_EQ(r.outliers.non_finite, std::vector<int>{7000});
  ASSERT_EQ(r.outliers.reasons.size(), 2u);
  EXPECT_TRUE(Contains(r.outliers.reasons[0], "sample 3000 (t = 6 s): residual of the fit on knee -1e+300")) << r.outliers.reasons[0];
  EXPECT_EQ(r.outliers.reasons[1], "sample 7000 (t = 14 s): the regressor or the prior's prediction is not finite (qd_hip = 1e+300)");
  EXPECT_TRUE(r.fit.x.allFinite());
  EXPECT_TRUE(r.fit.lm.converged()) << ToString(r.fit.lm.reason);
  EXPECT_TRUE(std::isfinite(r.equations.btb));
  EXPECT_TRUE(r.equations.AtA.allFinite());
  EXPECT_LT(HeldOutRms(leg, r.fit.x), 1.2 * leg.clean_rms);
}

// A burst of 20 consecutive rows whose hip torque reads a saturation code (327.67 N m, a 16-bit
// count of 0.01 N m): all 20 go, nothing else.
TEST(RobustIdentification, BurstOfGlitchedRowsIsRejected) {
  const Leg& leg = TheLeg();
  JointSamples train = leg.train;
  std::vector<int> burst;
  for (int i = 4000; i < 4020; ++i) {
    train.tau(i, leg.hip) = 327.67;
    burst.push_back(i);
  }
  const RobustIdentificationResult r = IdentifyJointModelRobust(leg.model, train, JointIdentificationOptions());
  EXPECT_EQ(r.outliers.rejected, burst) << FirstReason(r.outliers);
  EXPECT_EQ(r.outliers.reasons.size(), 5u);
  const double robust_rms = HeldOutRms(leg, r.fit.x);
  const double plain_rms = HeldOutRms(leg, IdentifyJointModel(leg.model, AccumulateNormalEquations(leg.model, train)).x);
  std::cerr << "burst: held-out RMS robust " << robust_rms << " (ratio " << robust_rms / leg.clean_rms << "), plain "
            << plain_rms << " (ratio " << plain_rms / leg.clean_rms << ")\n";
  EXPECT_LT(robust_rms, 1.2 * leg.clean_rms);
  EXPECT_GT(plain_rms, 2.0 * leg.clean_rms);
}

// The message helper for a fit that ends non-finite names the sample, time, column and value.
TEST(RobustIdentification, DescribeExtremeValuesNamesTheGlitch) {
  const Leg& leg = TheLeg();
  JointSamples train = leg.train;
  EXPECT_TRUE(DescribeExtremeValues(train).empty());
  train.tau(3000, leg.knee) = 1e300;
  train.qd(7000, leg.hip) = std::numeric_limits<double>::quiet_NaN();
  const std::vector<std::string> items = DescribeExtremeValues(train);
  ASSERT_EQ(items.size(), 2u);
  EXPECT_EQ(items[0], "sample 7000 (t = 14 s): qd_hip = nan (not finite)");
  EXPECT_TRUE(Contains(items[1], "sample 3000 (t = 6 s): tau_knee = 1e+300, ")) << items[1];
}

}  // namespace
}  // namespace inertial
