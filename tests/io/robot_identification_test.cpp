// Identification of the bundled robots (examples/leg3.urdf, examples/arm7.urdf) from simulated logs
// with known parameters: the project's forward-dynamics simulator tracks a Fourier excitation with
// the true robot (perturbed links, friction, rotors), the torques get Gaussian noise, and the fit
// must reach the noise floor on a fresh trajectory with every body physically consistent, where
// linear least squares on the same data gives impossible bodies.
#include <gtest/gtest.h>

#include <Eigen/QR>
#include <cmath>

#include "inertial/inertia/consistency.hpp"
#include "inertial/io/identification_report.hpp"
#include "inertial/model/fourier_trajectory.hpp"
#include "inertial/model/joint_simulation.hpp"
#include "test_support.hpp"

namespace inertial {
namespace {

std::string Example(const std::string& file) {
  const char* dir = std::getenv("INERTIAL_SOURCE_DIR");
  return std::string(dir != nullptr ? dir : ".") + "/examples/" + file;
}

struct Simulated {
  JointSamples train, test_clean, test;
};

// The truth: every body's theta drawn in [-0.25, 0.25] (masses within about +-40 %, COM shifts of
// centimetres), effect coefficients given; data tracked along two different Fourier trajectories.
Simulated Simulate(const RobotDynamics& model, const Eigen::VectorXd& x_true, double sigma_tau, double seconds,
                   std::uint64_t seed) {
  const JointDynamicsFn plant = [&](const Eigen::VectorXd& q, const Eigen::VectorXd& qd, const Eigen::VectorXd& qdd) {
    return model.InverseDynamics(x_true, q, qd, qdd);
  };
  JointSimulationOptions options;
  options.duration = seconds;
  options.sample_rate_hz = 500;
  options.internal_step = 1e-3;
  options.kp = Eigen::VectorXd::Constant(1, 300);
  options.kd = Eigen::VectorXd::Constant(1, 30);
  const int n = model.num_dofs();
  const FourierTrajectory train_ref = RandomFourierTrajectory(n, 5, 0.1, 0.9, seed);
  const FourierTrajectory test_ref = RandomFourierTrajectory(n, 5, 0.1, 0.9, seed + 1);
  Simulated s;
  s.train = AddGaussianNoise(SimulateTracking(plant, plant, [&](double t) { return train_ref.Evaluate(t); }, options,
                                              model.dof_names()),
                             SampleNoise{0, 0, 0, sigma_tau}, seed + 2);
  s.test_clean = SimulateTracking(plant, plant, [&](double t) { return test_ref.Evaluate(t); }, options, model.dof_names());
  s.test = AddGaussianNoise(s.test_clean, SampleNoise{0, 0, 0, sigma_tau}, seed + 3);
  return s;
}

Eigen::VectorXd TrueParameters(const RobotDynamics& model, const std::vector<double>& effect_values, std::uint64_t seed) {
  testing::Rng rng(seed);
  Eigen::VectorXd coeffs(model.num_features() - model.num_inertia_features());
  for (int k = 0; k < coeffs.size(); ++k) coeffs[k] = effect_values[k % effect_values.size()];
  Eigen::VectorXd x = model.ParametersFromEffectCoefficients(coeffs);
  for (int i = 0; i < 10 * static_cast<int>(model.bodies().size()); ++i) x[i] = rng.Uniform(-0.25, 0.25);
  return x;
}

void ExpectIdentified(const RobotDynamics& model, const Eigen::VectorXd& x_true, double sigma) {
  const Simulated s = Simulate(model, x_true, sigma, 40.0, 7);
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
