/// @file simulated_robot.hpp
/// Simulated logs of the bundled robots with known parameters, shared by the identification tests:
/// the project's forward-dynamics simulator tracks a Fourier excitation with the true robot, and
/// the torques get Gaussian noise.
#pragma once

#include <cstdlib>
#include <stdexcept>
#include <string>
#include <vector>

#include "inertial/model/fourier_trajectory.hpp"
#include "inertial/model/joint_simulation.hpp"
#include "inertial/model/robot_dynamics.hpp"
#include "test_support.hpp"

namespace inertial::testing {

/// examples/<file> of the source tree (INERTIAL_SOURCE_DIR, set by CTest).
inline std::string Example(const std::string& file) {
  const char* dir = std::getenv("INERTIAL_SOURCE_DIR");
  return std::string(dir != nullptr ? dir : ".") + "/examples/" + file;
}

struct SimulatedLogs {
  JointSamples train, test_clean, test;
};

/// Two different Fourier trajectories (5 harmonics, 0.1 Hz base) tracked by the true robot x_true
/// for `seconds` at `rate_hz`; train and test get torque noise sigma_tau, test_clean none.
inline SimulatedLogs SimulateLogs(const RobotDynamics& model, const Eigen::VectorXd& x_true, double sigma_tau,
                                  double seconds, std::uint64_t seed, double rate_hz = 500) {
  const JointDynamicsFn plant = [&](const Eigen::VectorXd& q, const Eigen::VectorXd& qd, const Eigen::VectorXd& qdd) {
    return model.InverseDynamics(x_true, q, qd, qdd);
  };
  JointSimulationOptions options;
  options.duration = seconds;
  options.sample_rate_hz = rate_hz;
  options.internal_step = 5e-4;
  const int n = model.num_dofs();
  const FourierTrajectory train_ref = RandomFourierTrajectory(n, 5, 0.1, 0.9, seed);
  const FourierTrajectory test_ref = RandomFourierTrajectory(n, 5, 0.1, 0.9, seed + 1);
  SetTrackingGainsFromInertia(plant, train_ref.Evaluate(0.0).q, 5.0, 0.7, &options);
  SimulatedLogs s;
  s.train = AddGaussianNoise(SimulateTracking(plant, plant, [&](double t) { return train_ref.Evaluate(t); }, options,
                                              model.dof_names()),
                             SampleNoise{0, 0, 0, sigma_tau}, seed + 2);
  s.test_clean = SimulateTracking(plant, plant, [&](double t) { return test_ref.Evaluate(t); }, options, model.dof_names());
  s.test = AddGaussianNoise(s.test_clean, SampleNoise{0, 0, 0, sigma_tau}, seed + 3);
  // A diverged fixed-step integration would still satisfy the dynamics, far off the excitation.
  for (int i = 0; i < s.test_clean.size(); ++i) {
    if ((s.test_clean.q.row(i).transpose() - test_ref.Evaluate(s.test_clean.t[i]).q).cwiseAbs().maxCoeff() > 0.09) {
      throw std::runtime_error("SimulateLogs: the simulation left the excitation trajectory (unstable integration)");
    }
  }
  return s;
}

/// The truth: every body's theta uniform in [-0.25, 0.25] (masses within about +-40 %, COM shifts
/// of centimetres); effect coefficients from `effect_values`, cycled.
inline Eigen::VectorXd TrueParameters(const RobotDynamics& model, const std::vector<double>& effect_values,
                                      std::uint64_t seed) {
  Rng rng(seed);
  Eigen::VectorXd coeffs(model.num_features() - model.num_inertia_features());
  for (int k = 0; k < coeffs.size(); ++k) coeffs[k] = effect_values[k % effect_values.size()];
  Eigen::VectorXd x = model.ParametersFromEffectCoefficients(coeffs);
  for (int i = 0; i < 10 * static_cast<int>(model.bodies().size()); ++i) x[i] = rng.Uniform(-0.25, 0.25);
  return x;
}

}  // namespace inertial::testing
