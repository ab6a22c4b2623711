/// @file gain_identification.hpp
/// Joints whose log holds a motor current (or any quantity) proportional to the joint torque with an
/// unknown gain: y_j = g_j tau_j, g_j > 0 [log unit per N m] (the `gain@joint` effect,
/// joint_effect.hpp). The gains are fitted with everything else: eq. 14 with the torque of each such
/// joint replaced by h_j y_j, h_j = 1 / g_j,
///
///   min_{x, h}  sum_{j without gain} ||A_j w(x) - b_j||^2 + sum_{j with gain} ||A_j w(x) - (h_j y_j + b_j)||^2
///               + gamma sum_b d(J_b || J_b,prior),
///
/// where b holds what is known: the measured torque of a joint without a gain, minus the torque of
/// any known body the model does not hold (a run's known payload, model/body_torques.hpp; b_j is
/// minus that torque for a joint with a gain). Each h_j enters linearly, so it is eliminated exactly
/// (variable projection, Golub and Pereyra 1973): for given w the best h_j is
/// (A_j w - b_j)^T y_j / y_j^T y_j, and putting it back leaves eq. 14 in w alone with the statistics
///
///   A^T A - sum_j a_j a_j^T / (y_j^T y_j),  A^T b + ... (GainProblem::Eliminated),   a_j = A_j^T y_j,
///
/// which IdentifyJointModel solves as it solves any other; the gains follow from the fitted w.
///
/// Not yet: standard deviations of the gains (a first Gauss-Newton estimate came out several times
/// smaller than the errors seen, so none is printed), and the regularizer's pull on the scale the
/// gains share (with links 25 % off their URDF, 0.5 % on the leg's knee without noise) is not
/// corrected.
///
/// What fixes the scale: scaling every link, effect and h by c leaves every gain joint's residual
/// scaled by c; only what is known in N m (a joint without a gain, a known payload, a link held at
/// its URDF) stops the fit from shrinking everything. Without any of them the gains are not
/// identifiable and the fit is refused (GainScaleProblem).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "inertial/estimation/batch/joint_identification.hpp"

namespace inertial {

/// The gain joints' statistics beside the links' (b as above).
struct GainProblem {
  JointNormalEquations links;   ///< A^T A, A^T b, b^T b over every joint's rows
  std::vector<int> dofs;        ///< the joints with a gain, ascending
  std::vector<Eigen::VectorXd> Aty;  ///< per gain joint: A_j^T y_j
  std::vector<double> yty, ytb;      ///< per gain joint: y_j^T y_j, y_j^T b_j
  /// Per DOF: A_j^T A_j, A_j^T y_j, y_j^T y_j (y: the log as it is) and A_j^T p_j, p_j^T p_j, y_j^T p_j
  /// (p: the known torque), for the fit in the log's own space (IdentifyWithGains).
  std::vector<JointNormalEquations> logged, known;
  std::vector<double> ytp;

  /// The statistics of the problem in w alone, every h_j at its best for w.
  JointNormalEquations Eliminated() const;
  /// h_j = 1 / g_j at coefficients w (one per gain joint): (A_j w - b_j)^T y_j / y_j^T y_j.
  Eigen::VectorXd InverseGains(const Eigen::VectorXd& w) const;
};

/// Accumulates GainProblem from samples whose tau holds what each joint logs (y for gain joints)
/// and `known` (rows = samples, columns = DOFs; empty: none), the torque of known bodies the model
/// does not hold. @throws std::invalid_argument if sizes disagree, a DOF is out of range or
/// repeated, or a gain joint logs nothing but zeros (naming it).
GainProblem AccumulateGainProblem(const RobotDynamics& model, const JointSamples& data, const Eigen::MatrixXd& known,
                                  const std::vector<int>& gain_dofs);

/// Why the torque scale is not fixed (every joint has a gain, nothing known in N m: no known
/// torque, no frozen body, no body whose mass is held: its alpha among held_parameters, as
/// JointIdentificationOptions), naming the joints and what would fix it; nullopt if it is fixed.
std::optional<std::string> GainScaleProblem(const RobotDynamics& model, const Eigen::MatrixXd& known,
                                            const std::vector<int>& gain_dofs, const std::vector<bool>& frozen_bodies,
                                            const std::vector<int>& held_parameters = {});

struct GainIdentificationResult {
  JointIdentificationResult fit;  ///< of the eliminated problem: x of the model
  Eigen::VectorXd gains;          ///< g_j per gain joint [log unit per N m]
};

/// Fits x and the gains: from the eliminated problem's answer, Levenberg-Marquardt over (x, log g)
/// of sum_j ||y_j - g_j (A_j w + p_j)||^2 / gbar_j^2 + gamma sum_b d (gbar: the start's gains, fixed,
/// so that each joint weighs in N m as in eq. 14). In the log's space the noise is on the target; in
/// the torque-space form above, y is a regressor carrying the noise, which shrinks h (regression
/// dilution): +0.66 % on the leg's knee over 20 noise seeds (sd 0.11 %), 40 % on a weakly driven
/// wrist. @throws std::invalid_argument as IdentifyJointModel, and if a gain comes
/// out non-positive (the log's sign is opposite to the torque's, or nothing in it follows the model),
/// naming the joint.
GainIdentificationResult IdentifyWithGains(const RobotDynamics& model, const GainProblem& problem,
                                           const JointIdentificationOptions& options = {});

}  // namespace inertial
