/// @file simulated_robot.hpp
/// Simulated logs of the bundled robots with known parameters, shared by the identification tests:
/// the project's forward-dynamics simulator tracks a Fourier excitation with the true robot, and
/// the torques get Gaussian noise.
#pragma once

#include <cstdlib>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Eigenvalues>

#include "inertial/inertia/closed_form_bodies.hpp"
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
  const Eigen::VectorXd w = model.Coefficients(x_true);
  const JointDynamicsFn plant = [&](const Eigen::VectorXd& q, const Eigen::VectorXd& qd, const Eigen::VectorXd& qdd) {
    return model.InverseDynamicsFromCoefficients(w, q, qd, qdd);
  };
  JointSimulationOptions options;
  options.duration = seconds;
  options.sample_rate_hz = rate_hz;
  options.internal_step = 5e-4;
  const int n = model.num_dofs();
  const FourierTrajectory train_ref = RandomFourierTrajectory(n, 5, 0.1, 0.9, seed);
  const FourierTrajectory test_ref = RandomFourierTrajectory(n, 5, 0.1, 0.9, seed + 1);
  const double bandwidth = 2 * M_PI * 5.0;  // computed torque: a 5 Hz, 0.7-damped loop per joint
  options.kp = Eigen::VectorXd::Constant(1, bandwidth * bandwidth);
  options.kd = Eigen::VectorXd::Constant(1, 2 * 0.7 * bandwidth);
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

/// The truth: every body's theta uniform in [-spread, spread] (0.25: masses within about +-40 %,
/// COM shifts of centimetres; 0.1: within about +-20 %, the ordinary error of a CAD model), each body
/// then pulled back toward its prior until it is well inside its region (ShrinkIntoRegion); effect
/// coefficients from `effect_values`, cycled.
inline Eigen::VectorXd TrueParameters(const RobotDynamics& model, const std::vector<double>& effect_values,
                                      std::uint64_t seed, double spread = 0.25) {
  Rng rng(seed);
  Eigen::VectorXd coeffs(model.num_features() - model.num_inertia_features());
  for (int k = 0; k < coeffs.size(); ++k) coeffs[k] = effect_values[k % effect_values.size()];
  Eigen::VectorXd x = model.ParametersFromEffectCoefficients(coeffs);
  for (int i = 0; i < 10 * static_cast<int>(model.bodies().size()); ++i) x[i] = rng.Uniform(-spread, spread);
  // A robot's links stay inside the regions they could occupy (body_region.hpp): a draw that leaves
  // one is pulled back toward the prior until it is well inside (the fit's barrier acts only nearer
  // the edge, so the truth is one the fit can reach without it).
  for (size_t e = 0; e < model.bodies().size(); ++e) {
    const EstimatedBody& b = model.bodies()[e];
    if (b.region) x.segment<10>(10 * static_cast<int>(e)) = ShrinkIntoRegion(b.map, *b.region, x.segment<10>(10 * static_cast<int>(e)));
  }
  return x;
}

/// The truth as a CAD model's ordinary error makes it: every body's mass times U(0.8, 1.25), its COM
/// moved by up to 0.3 of its size (rho0 = sqrt(tr(Sigma0) / m0), centimetres for a leg's links) in a
/// random direction, its principal second moments times U(0.7, 1.4) each (departure factors up to
/// about 1.4, inside the diagnosis's prior tolerance); effect coefficients as TrueParameters.
inline Eigen::VectorXd CadErrorParameters(const RobotDynamics& model, const std::vector<double>& effect_values,
                                          std::uint64_t seed) {
  Eigen::VectorXd x = TrueParameters(model, effect_values, seed, 0.0);
  Rng rng(seed + 100);
  for (size_t e = 0; e < model.bodies().size(); ++e) {
    const InertialParams& prior = model.bodies()[e].prior;
    const Matrix3 I0 = prior.rotational_inertia_about_com();
    const Matrix3 sigma0 = 0.5 * I0.trace() * Matrix3::Identity() - I0;
    const Eigen::SelfAdjointEigenSolver<Matrix3> eig(sigma0);
    Matrix3 R = eig.eigenvectors();
    if (R.determinant() < 0) R.col(0) = -R.col(0);
    const double rho0 = std::sqrt(sigma0.trace() / prior.mass());
    Vector3 direction = rng.UniformVector<3>(-1, 1);
    direction /= std::max(direction.norm(), 1e-9);
    const Vector3 com = prior.com() + rng.Uniform(0, 0.3) * rho0 * direction;
    Vector3 L = eig.eigenvalues();
    for (int k = 0; k < 3; ++k) L[k] *= rng.Uniform(0.7, 1.4);
    const double m = prior.mass() * rng.Uniform(0.8, 1.25);
    // Second moments per unit mass kept, scaled: L is a mass-weighted quantity.
    const InertialParams body = BodyFromSecondMoments(m, L * (m / prior.mass()), Pose{R, com});
    x.segment<10>(10 * static_cast<int>(e)) = model.bodies()[e].map.ThetaOf(body);
  }
  return x;
}

}  // namespace inertial::testing
