// Identification of the bundled robots (examples/leg3.urdf, examples/arm7.urdf) from simulated logs
// with known parameters: the project's forward-dynamics simulator tracks a Fourier excitation with
// the true robot (perturbed links, friction, rotors), the torques get Gaussian noise, and the fit
// must reach the noise floor on a fresh trajectory with every body physically consistent, where
// linear least squares on the same data gives impossible bodies.
#include <gtest/gtest.h>

#include <Eigen/QR>
#include <cmath>

#include "inertial/inertia/consistency.hpp"
#include "inertial/report/identification_report.hpp"
#include "simulated_robot.hpp"

namespace inertial {
namespace {

using testing::Example;
using testing::SimulatedLogs;
using testing::TrueParameters;

void ExpectIdentified(const RobotDynamics& model, const Eigen::VectorXd& x_true, double sigma) {
  const SimulatedLogs s = testing::SimulateLogs(model, x_true, sigma, 40.0, 7);
  const JointNormalEquations eq = AccumulateNormalEquations(model, s.train);
  const IdentificationRun run = RunIdentification(model, s.train, &s.test, JointIdentificationOptions());
  ASSERT_TRUE(run.fit.lm.converged()) << ToString(run.fit.lm.reason) << " after " << run.fit.lm.iterations;
  // The identifiable combinations: the fit predicts the noise-free torques of a trajectory it never
  // saw to a small fraction of the noise, and the noisy ones to the noise floor.
  const TorqueErrors clean = CompareTorques(PredictJointTorques(model, run.fit.x, s.test_clean), s.test_clean.tau);
  std::cerr << model.bodies().size() << " bodies, " << model.num_parameters() << " parameters: validation RMS "
            << run.fit_validation->total_rms << " N m (noise " << sigma << "), against noise-free torques "
            << clean.total_rms << ", prior " << run.prior_validation->total_rms << "; " << run.fit.lm.iterations
            << " iterations\n";
  EXPECT_LT(clean.total_rms, 0.25 * sigma);
  EXPECT_LT(run.fit_validation->total_rms, 1.05 * sigma);
  EXPECT_GT(run.prior_validation->total_rms, 3.0 * sigma);
  for (int e = 0; e < static_cast<int>(model.bodies().size()); ++e) {
    EXPECT_TRUE(CheckConsistency(model.BodyInertia(e, run.fit.x)).fully_consistent()) << model.bodies()[e].name;
  }
  // Linear least squares on pi (the minimum-norm solution of the rank-deficient problem).
  const Eigen::VectorXd w = eq.AtA.completeOrthogonalDecomposition().solve(eq.Atb);
  int impossible = 0;
  for (int b = 0; b < model.tree().num_bodies(); ++b) {
    impossible += !CheckConsistency(InertialParams::FromVector(w.segment<10>(10 * b))).fully_consistent();
  }
  std::cerr << "linear least squares: " << impossible << " of " << model.tree().num_bodies() << " bodies impossible\n";
  EXPECT_GT(impossible, 0);
}

TEST(RobotIdentification, Leg3WithRotorsAndFrictionFromASimulatedLog) {
  const RobotModel robot = LoadUrdf(Example("leg3.urdf"));
  const RobotDynamics model =
      MakeRobotDynamics(robot, ParseEffectList("viscous,coulomb:scale=0.05,rotor@abad:gear=6,rotor@hip:gear=6,rotor@knee:gear=9.33"));
  EXPECT_EQ(model.num_parameters(), 66);  // the "about 66": 6 bodies x 10 + 2 x 3 friction
  ExpectIdentified(model, TrueParameters(model, {0.2, 0.2, 0.2, 0.5, 0.5, 0.5}, 3), 0.3);
}

TEST(RobotIdentification, Arm7WithFrictionAndOffsetsFromASimulatedLog) {
  const RobotModel robot = LoadUrdf(Example("arm7.urdf"));
  const RobotDynamics model = MakeRobotDynamics(robot, ParseEffectList("viscous,coulomb:scale=0.05,offset"));
  ExpectIdentified(model, TrueParameters(model, {0.3, 0.3, 0.3, 0.3, 0.3, 0.3, 0.3, 0.8, 0.8, 0.8, 0.8, 0.8, 0.8, 0.8,
                                                 0.5, -0.5, 0.2, 0.1, -0.1, 0.05, 0.02}, 4),
                   0.5);
}

}  // namespace
}  // namespace inertial
