/// @file closed_loop_rate.hpp
/// How fast a simulated robot's loop can move, and how many explicit Runge-Kutta steps per sample
/// interval that asks for (joint_simulation.hpp uses both).
///
/// The simulator integrates the plant id(q, qd, qdd) = tau by classical RK4 with the command tau
/// held over each step (a controller running at the step rate). With x = (q, qd), M the mass
/// matrix (the qdd coefficient of id) at q, P = (d id/dq, d id/dqd) the plant's slopes at fixed
/// qdd and C = (dtau/dq, dtau/dqd) the command's, two linearizations matter:
///
///   J(C) = [ 0                       I                      ]
///          [ M^-1 (C_q - P_q)        M^-1 (C_qd - P_qd)      ]
///
/// - the held-command plant J(0): what RK4 integrates within a step. It holds everything the plant
///   adds: a viscous or Coulomb friction slope (d id/dqd; tanh(qd / v_s) is steepest at qd = 0,
///   slope bc / v_s), springs and gravity (d id/dq), Coriolis terms;
/// - the closed loop J(C): what the held command follows from step to step (the feedback gains,
///   and whatever of the plant the command cancels: computed-torque control cancels all of it).
///
/// The rate of each is rho = max |lambda| over its eigenvalues [1/s]; the steps follow the larger.
///
/// Why both, and the constant. RK4 is stable on y' = lambda y for h lambda inside its stability
/// region, which reaches |h lambda| = 2.785 on the negative real axis and 2.828 on the imaginary
/// axis: that bounds h rho of J(0). With the command held, one step maps x to
/// x + h phi(h J(0)) J(C) x to first order (phi(z) = 1 + z/2 + z^2/6 + z^3/24, RK4's R(z) = 1 + z phi(z)):
/// for modes the feedback drives, forward Euler on J(C), stable for |1 + h lambda| < 1: h |lambda|
/// < 2 on the real axis, h rho < 2 zeta for a mode of damping ratio zeta (exactly, PD feedback of
/// bandwidth w and damping zeta held over steps of h on a mass is stable for h w < 1 / zeta and
/// h w < 4 zeta: h rho < 1.43 at the simulator's usual zeta = 0.7, the tighter limit); and phi(h
/// J(0)) grows without bound outside RK4's region, so a stiff plant mode breaks the held step even
/// where the command cancels it. The rule below keeps h rho <= kStepRateLimit = 1 for both: a
/// factor 1.43 inside the held feedback's limit at zeta = 0.7 (any mode with zeta >= 0.5 stays
/// stable), 2.8 inside RK4's for the plant's real (friction, damping) modes. That margin is needed
/// because rho is measured once per sample interval while a joint's friction slope can grow
/// within it (a velocity reversal). At h rho = 1 RK4's error per step on the fastest mode is about
/// (h rho)^5 / 120 < 1 %: the log is accurate, not only bounded.
/// Conventions: SI units; x = (q, qd) stacked, q first.
#pragma once

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include "inertial/model/joint_simulation.hpp"

namespace inertial {

/// A torque's sensitivity to the state: d/dq and d/dqd (n x n each), of the command at one time
/// (CommandSlopes) or of the plant's inverse dynamics at a fixed qdd (PlantSlopes).
struct StateSlopes {
  Eigen::MatrixXd dq, dqd;
};
using CommandSlopes = StateSlopes;
using PlantSlopes = StateSlopes;

/// The slopes of PD feedback tau = ff(t) + kp (q_ref - q) + kd (qd_ref - qd) (the feedforward
/// depends on time only): dq = -diag(kp), dqd = -diag(kd). kp and kd have one entry per joint.
/// @throws std::invalid_argument if their sizes differ.
CommandSlopes PdCommandSlopes(const Eigen::VectorXd& kp, const Eigen::VectorXd& kd);

/// The slopes of any controller at time t and state (q, qd), where it returned `tau`, by forward
/// differences (2n controller calls; step sqrt(machine epsilon) max(1, |x_k|)).
/// @throws std::invalid_argument if the controller returns a wrong size.
CommandSlopes DifferencedCommandSlopes(const JointControllerFn& controller, double t, const Eigen::VectorXd& q,
                                       const Eigen::VectorXd& qd, const Eigen::VectorXd& tau);

/// The plant's slopes d id/dq and d id/dqd at (q, qd, qdd), qdd fixed, by forward differences
/// (2n + 1 plant calls, steps as above).
/// @throws std::invalid_argument on wrong sizes or a plant returning a wrong size.
PlantSlopes DifferencedPlantSlopes(const JointDynamicsFn& plant, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                                   const Eigen::VectorXd& qdd);

/// J(C) above (2n x 2n) from the Cholesky factorization of M(q) (the simulator has it from its
/// own forward dynamics at the state) and the slopes: one (n x 2n) solve. The held-command plant
/// is LoopJacobian(mass, plant, zero command slopes).
/// @throws std::invalid_argument if the sizes do not agree.
Eigen::MatrixXd LoopJacobian(const Eigen::LLT<Eigen::MatrixXd>& mass, const PlantSlopes& plant,
                             const CommandSlopes& command);

/// The closed loop's J(C) at (q, qd) with qdd = f(q, qd), the forward dynamics under the command:
/// LoopJacobian(mass, DifferencedPlantSlopes(plant, q, qd, qdd), command).
Eigen::MatrixXd ClosedLoopJacobian(const JointDynamicsFn& plant, const Eigen::LLT<Eigen::MatrixXd>& mass,
                                   const Eigen::VectorXd& q, const Eigen::VectorXd& qd, const Eigen::VectorXd& qdd,
                                   const CommandSlopes& command);

/// The rate the steps must follow: the larger spectral radius of the held-command plant J(0) and
/// the closed loop J(C) (two eigenvalue problems of 2n x 2n).
double StepRate(const Eigen::LLT<Eigen::MatrixXd>& mass, const PlantSlopes& plant, const CommandSlopes& command);

/// rho = max |lambda| over the eigenvalues of a square matrix (Eigen's Hessenberg and real Schur
/// forms, no eigenvectors: about 0.5 ms for 56 x 56 here). +infinity if `a` has a non-finite entry
/// or the eigenvalue iteration fails (a matrix no step can follow).
double SpectralRadius(const Eigen::MatrixXd& a);

/// The largest h rho the simulator allows, for StepRate's rho (see the file comment: 1.43 times
/// inside the held feedback's stability limit at damping 0.7, 2.8 times inside RK4's on the real
/// axis).
constexpr double kStepRateLimit = 1.0;
/// The shortest RK4 step the simulator takes [s]: 2000 steps per sample interval at 1 kHz. A loop
/// that needs shorter ones (rho > kStepRateLimit / kShortestStep = 2e6 1/s: a friction slope or
/// gain no physical robot has, or a state running away) is reported as diverged rather than
/// simulated for hours. A bound on the step, not on the count, so that a low sample rate (long
/// intervals) does not refuse a robot a high one simulates.
constexpr double kShortestStep = 5e-7;

/// The steps for one sample interval of `sample_period` seconds: max(base_steps,
/// ceil(sample_period rho / kStepRateLimit)). Returned as a double, which may be beyond
/// MaxStepsPerSample (the caller refuses it) and is +infinity for a rho that is not finite.
/// @throws std::invalid_argument if sample_period is not positive and finite, base_steps < 1 or
/// rho < 0.
double StepsPerSample(double sample_period, double rho, int base_steps);

/// The most steps an interval of `sample_period` seconds may have: floor(sample_period /
/// kShortestStep), at most 1e9, at least 1 (2000 at 1 kHz).
/// @throws std::invalid_argument if sample_period is not positive and finite.
double MaxStepsPerSample(double sample_period);

}  // namespace inertial
