/// @file joint_identification.hpp
/// Batch identification of a robot's links, rotors, payloads and joint effects from joint-space
/// samples: the paper's regularized problem (eq. 14),
///
///   min_x  sum_j || A_j w(x) - tau_j ||^2  +  gamma sum_bodies d(J_b(theta_b) || J_b,prior),
///
/// solved by Levenberg-Marquardt over x (log-Cholesky theta relative to each prior plus effect
/// parameters, robot_dynamics.hpp), so every iterate is physically consistent. d is the log-det
/// divergence (log_det_divergence.hpp), which fixes the directions the data cannot see. Every body
/// with a region (EstimatedBody::region) is kept inside it by a smooth barrier added to the cost
/// (region_barrier.hpp), so every iterate is a body the robot could have, not only a consistent one.
/// With the robot's weighed mass (JointIdentificationOptions::total_mass), a barrier of the same kind
/// keeps the links' masses from adding up to more (total_mass_barrier.hpp).
/// The data enter only through A^T A, A^T tau and tau^T tau (accumulated once; each iteration then
/// costs O(parameters^3), independent of the number of samples).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "inertial/estimation/batch/dense_levenberg_marquardt.hpp"
#include "inertial/estimation/batch/total_mass_barrier.hpp"
#include "inertial/model/joint_samples.hpp"
#include "inertial/model/robot_dynamics.hpp"

namespace inertial {

/// Sufficient statistics of the data for the linear model tau = A w.
struct JointNormalEquations {
  Eigen::MatrixXd AtA;  ///< num_features x num_features
  Eigen::VectorXd Atb;
  double btb = 0.0;
  int num_samples = 0;
};

/// Accumulates A^T A, A^T tau, tau^T tau over every sample (joint columns in the model's DOF order).
/// @throws std::invalid_argument if the samples' joints differ from the model's DOFs or sizes disagree.
JointNormalEquations AccumulateNormalEquations(const RobotDynamics& model, const JointSamples& data);

/// The same statistics for each joint's rows alone (element k: the torque equations of DOF k), so
/// that per-joint errors of any w follow without the data: their sum is AccumulateNormalEquations.
/// @throws as AccumulateNormalEquations.
std::vector<JointNormalEquations> AccumulateJointwiseNormalEquations(const RobotDynamics& model,
                                                                     const JointSamples& data);

/// ||A w - tau||^2 from the statistics: w^T A^T A w - 2 w^T A^T tau + tau^T tau (negative rounding
/// floored at 0; NaN if w or the statistics are not finite).
double SquaredError(const JointNormalEquations& eq, const Eigen::VectorXd& w);

struct JointIdentificationOptions {
  double prior_weight = 1e-2;  ///< gamma of eq. 14 (the paper's value)
  /// Stops when an iteration lowers the cost by less than 1e-7 of it (or on tiny steps or
  /// gradients). Levenberg damping with the Newton Hessian: with Marquardt's scaling the fit
  /// crawls for hundreds of iterations along directions only the regularizer holds.
  LevenbergMarquardtOptions lm{1000, 1e-7, 1e-10, 1e-10, 1e-3, false, {}};
  /// Damped Newton (the exact Hessian of the data term: Gauss-Newton plus the second derivatives
  /// of w(x), LogCholeskyParameterization::ContractedHessian) instead of Gauss-Newton. The damping
  /// keeps every step a descent step where that Hessian is indefinite.
  bool newton = true;
  /// One flag per estimated body (model.bodies() order), or empty: a flagged body is held at its
  /// prior (theta = 0), e.g. links whose URDF inertias are trusted while payloads are fitted.
  std::vector<bool> frozen_bodies;
  /// Entries of x held at their start value (indices), e.g. a payload's alpha: relative to its
  /// prior, m = e^{2 alpha} m_prior (the last row of U is e^alpha [0 0 0 1]), so alpha held at 0
  /// holds a known mass exactly while its COM and inertia are fitted.
  std::vector<int> held_parameters;
  /// Start of the fit (size num_parameters), or empty for the default start below.
  Eigen::VectorXd initial;
  /// The robot as weighed: the links' masses (estimated and frozen) plus what is fixed to the base
  /// kept at most its total (total_mass_barrier.hpp); none: no bound. A start beyond it is brought
  /// inside first (IntoTotalMassBound: the links whose mass may move scaled by one factor).
  std::optional<TotalMassBound> total_mass;
};

struct JointIdentificationResult {
  Eigen::VectorXd x;           ///< the identified parameters
  Eigen::VectorXd x_initial;   ///< the start: priors, effects from linear least squares
  double data_cost = 0.0;      ///< sum of squared torque errors at x
  double regularizer = 0.0;    ///< sum of d over bodies at x (unweighted)
  DenseLevenbergMarquardtResult lm;
};

/// The default start of IdentifyJointModel: the priors (theta = 0); effect coefficients at their
/// values in the linear least-squares fit of the whole model (frozen bodies held at their priors),
/// non-negative ones floored at 1e-3 of their feature's natural scale (see the implementation).
Eigen::VectorXd DefaultInitialParameters(const RobotDynamics& model, const JointNormalEquations& data,
                                         const std::vector<bool>& frozen_bodies = {});

/// The priors without any effect: theta = 0, offsets 0, every non-negative coefficient e^s with
/// s = log(1e-300) (zero to double precision), spring q0 = 0: the URDF's own prediction.
Eigen::VectorXd PriorParametersWithoutEffects(const RobotDynamics& model);

/// Zeroes the gradient g and decouples the Hessian H (unit diagonal) of every parameter that
/// options holds (frozen_bodies, held_parameters), so that no Levenberg-Marquardt step moves it.
/// g and H may extend beyond x (further parameters after it).
void HoldParameters(const JointIdentificationOptions& options, Eigen::VectorXd* g, Eigen::MatrixXd* H);

/// Fits from options.initial, or from DefaultInitialParameters.
/// @throws std::invalid_argument if the statistics, the start, frozen_bodies or held_parameters do
/// not match the model, the prior weight is negative or not finite, or total_mass is not a positive
/// finite bound or leaves no room for the links the fit may move (IntoTotalMassBound).
JointIdentificationResult IdentifyJointModel(const RobotDynamics& model, const JointNormalEquations& data,
                                             const JointIdentificationOptions& options = {});

/// Predicted torques A_j w(x) for every sample (rows = samples, columns = DOFs).
Eigen::MatrixXd PredictJointTorques(const RobotDynamics& model, const Eigen::VectorXd& x, const JointSamples& data);

/// Torque error measures per joint: RMS of (predicted - measured), and that RMS divided by the RMS
/// of the measured torque; totals over all joints pooled.
struct TorqueErrors {
  Eigen::VectorXd rms, relative_rms;
  double total_rms = 0.0, total_relative_rms = 0.0;
};
TorqueErrors CompareTorques(const Eigen::MatrixXd& predicted, const Eigen::MatrixXd& measured);

}  // namespace inertial
