/// @file joint_simulation.hpp
/// Joint-space simulation of a robot from its inverse dynamics, to produce data that look like an
/// excitation experiment: the plant's state (q, qd) is integrated with the classical fourth-order
/// Runge-Kutta method, driven by a torque command held constant over every internal step
/// (zero-order hold, as a controller running at the internal rate), and sampled at a fixed output
/// rate.
///
/// The plant is given by its full inverse dynamics tau = id(q, qd, qdd) (rigid bodies plus any
/// joint effects: friction, armature, springs), assumed affine in qdd with a symmetric positive
/// definite qdd coefficient (the mass matrix). Forward dynamics solve id(q, qd, qdd) = tau.
///
/// Sample times: t_i = start_time + i / sample_rate_hz for i = 0 .. floor(duration * rate), both
/// ends included. Each sample interval T is cut into equal steps, so that every sample instant is
/// a step boundary: at least ceil(T / internal_step) of them, and more where the loop is stiff. At
/// every sample the loop's rate rho is measured (closed_loop_rate.hpp, StepRate: the largest
/// |eigenvalue| of the plant's Jacobian under the held command and of the closed loop's) and the
/// interval gets StepsPerSample(T, rho, that count) steps, h rho <= 1, so that RK4 and the held
/// command stay stable whatever the robot, its gains and its friction. A loop that would need steps
/// shorter than kShortestStep (2000 per sample at 1 kHz) is reported as diverged. The rate is measured once per interval,
/// not per step: 2n + 1 plant calls and 2n controller calls (forward differences; the mass matrix
/// is the sample's own) and two eigenvalue problems of 2n x 2n. For the 28-joint chain (5.7 us
/// per inverse dynamics, 0.5 ms per 56 x 56 eigenvalue problem here) that is about 1.6 ms per
/// interval against 1.3 ms for each pair of RK4 steps (116 inverse dynamics per step).
/// At each sample the output holds the plant's state, the torque applied from that instant on, and
/// the plant's acceleration under that torque, so id(q_i, qd_i, qdd_i) = tau_i holds exactly.
///
/// Errors: a model whose mass matrix is not positive definite (or whose dynamics are not finite)
/// at the initial state is a model error (std::invalid_argument saying so). Past the initial state
/// the same failures, a state that becomes non-finite, or a loop too stiff to follow, mean the
/// simulation ran away: SimulationDiverged, "the simulation diverged at t = ... s (reason)".
/// Conventions: SI units; rows are samples (joint_samples.hpp).
#pragma once

#include <cstdint>
#include <functional>
#include <stdexcept>
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

/// The error of a simulation that ran away past its initial state: what() is "the simulation
/// diverged at t = <time> s (<reason>)".
class SimulationDiverged : public std::invalid_argument {
 public:
  SimulationDiverged(double time, const std::string& reason);
  double time() const { return time_; }              ///< [s] simulation time where it was seen
  const std::string& reason() const { return reason_; }

 private:
  double time_;
  std::string reason_;
};

/// What the integration did (SimulateJoints, SimulateTracking: optional output).
struct JointSimulationStats {
  double max_rate = 0.0;           ///< [1/s] the largest closed-loop rate rho measured at a sample
  double max_rate_time = 0.0;      ///< [s] where it was measured
  int min_steps_per_sample = 0;    ///< fewest RK4 steps in a sample interval (0: no interval)
  int max_steps_per_sample = 0;    ///< most RK4 steps in a sample interval
  long long total_steps = 0;       ///< RK4 steps in all
};

struct JointSimulationOptions {
  double start_time = 0.0;        ///< [s] time of the first sample
  double duration = 10.0;         ///< [s] >= 0
  double sample_rate_hz = 1000.0;  ///< output rate [Hz] > 0
  /// Largest integration (and control) step [s] > 0; a stiff closed loop gets smaller steps.
  double internal_step = 2e-4;
  /// Tracking gains (SimulateTracking only), acceleration per unit of error: one entry per joint,
  /// or one entry for all joints; >= 0. kp = w^2 and kd = 2 zeta w make every joint's error a
  /// loop of bandwidth w [rad/s] and damping ratio zeta (the defaults: w = 20 rad/s, zeta = 1).
  Eigen::VectorXd kp = Eigen::VectorXd::Constant(1, 400.0);  ///< [1/s^2]
  Eigen::VectorXd kd = Eigen::VectorXd::Constant(1, 40.0);   ///< [1/s]
  /// Optional: called after each output sample with the fraction of the samples done (0, 1].
  std::function<void(double fraction)> progress;
};

/// Simulates the plant from (q_start, qd_start) under an arbitrary controller (passive motion: a
/// controller returning zeros). joint_names (empty, or one per joint) are copied to the output;
/// `stats`, if given, receives what the integration did. The controller's slopes for the
/// closed loop's rate come from forward differences (closed_loop_rate.hpp).
/// @throws std::invalid_argument on bad options or sizes, or a model that is not one at the
/// initial state (the message gives the simulation time); SimulationDiverged past it.
JointSamples SimulateJoints(const JointDynamicsFn& plant, const JointControllerFn& controller,
                            const Eigen::VectorXd& q_start, const Eigen::VectorXd& qd_start,
                            const JointSimulationOptions& options, const std::vector<std::string>& joint_names = {},
                            JointSimulationStats* stats = nullptr);

/// Simulates the plant tracking `reference` from the reference's state at start_time under
/// computed-torque control: the command, at every internal step,
///   tau = nominal(q, qd, qdd_ref + kp (q_ref - q) + kd (qd_ref - qd)),
/// where `nominal` is the controller's (possibly approximate) model, or the plant itself. With the
/// plant as its own model the error e = q_ref - q obeys e'' + kd e' + kp e = 0 joint by joint,
/// whatever the robot: the nominal model at the measured state cancels its inertia, gravity,
/// Coriolis terms and friction, so the loop is as fast as kp and kd say and no faster.
///
/// Why not PD about the reference's feedforward (tau = nominal(q_ref, qd_ref, qdd_ref) + Kp e +
/// Kd e', diagonal gains scaled to an inertia): its error dynamics M e'' + Kd e' + (Kp + G) e = 0
/// leave the mass matrix M and the plant's stiffness G = d id/dq (gravity, the reference's
/// accelerations) in the loop. Gains from the mass matrix's diagonal, Kp = w^2 diag(M) and Kd =
/// 2 zeta w diag(M), made the fastest mode about 2 zeta w max|eig(M^-1 diag(M))|, and that
/// eigenvalue grows with a serial chain (6.9 for the leg, 8.2 for the arm, 50, 458 and 1536 for
/// the 7, 14 and 28-joint chains at q = 0.3): 67,540 1/s for the 28-joint chain, far beyond what
/// RK4 follows at 5e-4 s. Gains from the inertia each joint feels
/// with the others free, 1 / (M^-1)_jj, bound that factor by n (1.9 to 3.3 for those robots) but
/// are too weak for the gravity of an upright chain: the closed loop there has an eigenvalue of
/// real part +2.5, +5.8 and +7.2 1/s for the 7, 14 and 28-joint chains (it left the 28-joint
/// chain's excitation by 15 rad within 2 s). Computed torque needs neither.
/// @throws std::invalid_argument as SimulateJoints, and for gains of a wrong size or negative.
JointSamples SimulateTracking(const JointDynamicsFn& plant, const JointDynamicsFn& nominal,
                              const JointReferenceFn& reference, const JointSimulationOptions& options,
                              const std::vector<std::string>& joint_names = {}, JointSimulationStats* stats = nullptr);

/// Inverse-dynamics data without integration: at every sample time (as above; internal_step and
/// gains unused) the reference's q, qd, qdd and tau = id(q, qd, qdd).
/// @throws std::invalid_argument on bad options or sizes.
JointSamples SampleTrajectory(const JointDynamicsFn& id, const JointReferenceFn& reference,
                              const JointSimulationOptions& options, const std::vector<std::string>& joint_names = {});

/// Standard deviations of additive white Gaussian noise per signal (SI units of each signal).
struct SampleNoise {
  double q = 0.0, qd = 0.0, qdd = 0.0, tau = 0.0;
};

/// A copy of `samples` with independent zero-mean Gaussian noise added to every entry of q, qd, qdd
/// and tau (t and names unchanged); deterministic for a seed (std::mt19937_64, Box-Muller).
/// @throws std::invalid_argument if a standard deviation is negative or not finite.
JointSamples AddGaussianNoise(const JointSamples& samples, const SampleNoise& sigma, std::uint64_t seed);

}  // namespace inertial
