/// @file joint_simulation.hpp
/// Joint-space simulation of a robot from its inverse dynamics, to produce data that look like an
/// excitation experiment: the plant's state (q, qd) is integrated with the classical fourth-order
/// Runge-Kutta method at a fixed internal step, driven by a torque command held constant over every
/// internal step (zero-order hold, as a controller running at the internal rate), and sampled at a
/// fixed output rate.
///
/// The plant is given by its full inverse dynamics tau = id(q, qd, qdd) (rigid bodies plus any
/// joint effects: friction, armature, springs), assumed affine in qdd with a symmetric positive
/// definite qdd coefficient (the mass matrix). Forward dynamics solve id(q, qd, qdd) = tau.
///
/// Sample times: t_i = start_time + i / sample_rate_hz for i = 0 .. floor(duration * rate), both
/// ends included. The internal step actually used is the sample period divided by
/// ceil(sample period / internal_step), so that every sample instant is a step boundary. At each
/// sample the output holds the plant's state, the torque applied from that instant on, and the
/// plant's acceleration under that torque, so id(q_i, qd_i, qdd_i) = tau_i holds exactly.
/// Conventions: SI units; rows are samples (joint_samples.hpp).
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "inertial/model/fourier_trajectory.hpp"
#include "inertial/model/joint_samples.hpp"

namespace inertial {

/// Full inverse dynamics of a robot: tau = id(q, qd, qdd), affine in qdd.
using JointDynamicsFn =
    std::function<Eigen::VectorXd(const Eigen::VectorXd& q, const Eigen::VectorXd& qd, const Eigen::VectorXd& qdd)>;
/// A reference trajectory: q, qd, qdd at time t.
using JointReferenceFn = std::function<JointTrajectoryPoint(double t)>;
/// A torque command from the time and the measured state, evaluated once per internal step.
using JointControllerFn =
    std::function<Eigen::VectorXd(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd)>;

/// qdd with id(q, qd, qdd) = tau: bias h = id(q, qd, 0), mass matrix column k = id(q, qd, e_k) - h
/// (symmetrized), solved by Cholesky.
/// @throws std::invalid_argument if sizes differ, id returns a wrong size or non-finite numbers,
/// or the mass matrix is not positive definite.
Eigen::VectorXd ForwardDynamics(const JointDynamicsFn& id, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                                const Eigen::VectorXd& tau);

struct JointSimulationOptions {
  double start_time = 0.0;        ///< [s] time of the first sample
  double duration = 10.0;         ///< [s] >= 0
  double sample_rate_hz = 1000.0;  ///< output rate [Hz] > 0
  double internal_step = 2e-4;    ///< largest integration (and control) step [s] > 0
  /// Tracking gains (SimulateTracking only): one entry per joint, or one entry for all joints; >= 0.
  Eigen::VectorXd kp = Eigen::VectorXd::Constant(1, 400.0);  ///< [N m/rad]
  Eigen::VectorXd kd = Eigen::VectorXd::Constant(1, 40.0);   ///< [N m s/rad]
  /// Optional: called after each output sample with the fraction of the samples done (0, 1].
  std::function<void(double fraction)> progress;
};

/// Simulates the plant from (q_start, qd_start) under an arbitrary controller (passive motion: a
/// controller returning zeros). joint_names (empty, or one per joint) are copied to the output.
/// @throws std::invalid_argument on bad options or sizes, or if the state becomes non-finite or the
/// mass matrix singular (the message gives the simulation time).
JointSamples SimulateJoints(const JointDynamicsFn& plant, const JointControllerFn& controller,
                            const Eigen::VectorXd& q_start, const Eigen::VectorXd& qd_start,
                            const JointSimulationOptions& options, const std::vector<std::string>& joint_names = {});

/// Simulates the plant tracking `reference` from the reference's state at start_time, with the
/// computed-torque-feedforward PD command
///   tau = nominal(q_ref, qd_ref, qdd_ref) + kp (q_ref - q) + kd (qd_ref - qd),
/// where `nominal` is the controller's (possibly approximate) model, or the plant itself.
/// @throws std::invalid_argument as SimulateJoints, and for gains of a wrong size or negative.
JointSamples SimulateTracking(const JointDynamicsFn& plant, const JointDynamicsFn& nominal,
                              const JointReferenceFn& reference, const JointSimulationOptions& options,
                              const std::vector<std::string>& joint_names = {});

/// Inverse-dynamics data without integration: at every sample time (as above; internal_step and
/// gains unused) the reference's q, qd, qdd and tau = id(q, qd, qdd).
/// @throws std::invalid_argument on bad options or sizes.
JointSamples SampleTrajectory(const JointDynamicsFn& id, const JointReferenceFn& reference,
                              const JointSimulationOptions& options, const std::vector<std::string>& joint_names = {});

/// Standard deviations of additive white Gaussian noise per signal (SI units of each signal).
/// Tracking gains scaled to the robot's own inertia: per joint j, kp_j = w^2 M_jj, kd_j =
/// 2 zeta w M_jj with w = 2 pi bandwidth_hz and M_jj the mass matrix diagonal at q (from the
/// inverse dynamics: id(q, 0, e_j) - id(q, 0, 0)), so that light links do not make the fixed-step
/// integration unstable under stiff fixed gains. Writes options->kp and options->kd.
/// @throws std::invalid_argument if id returns a wrong size or a non-positive diagonal.
void SetTrackingGainsFromInertia(const JointDynamicsFn& id, const Eigen::VectorXd& q, double bandwidth_hz,
                                 double damping_ratio, JointSimulationOptions* options);

struct SampleNoise {
  double q = 0.0, qd = 0.0, qdd = 0.0, tau = 0.0;
};

/// A copy of `samples` with independent zero-mean Gaussian noise added to every entry of q, qd, qdd
/// and tau (t and names unchanged); deterministic for a seed (std::mt19937_64, Box-Muller).
/// @throws std::invalid_argument if a standard deviation is negative or not finite.
JointSamples AddGaussianNoise(const JointSamples& samples, const SampleNoise& sigma, std::uint64_t seed);

}  // namespace inertial
