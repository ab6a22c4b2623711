/// @file momentum_features.hpp
/// The robot's dynamics in momentum form, for rows that need no joint acceleration (issue 46; the
/// filtered momentum form of Slotine and Li's composite adaptive control, Automatica 1989).
///
/// With the generalized momentum p = M(q) qd (rotor inertias and payloads included: every term of
/// the model linear in qdd), Lagrange's equations read
///   tau = dp/dt - dT/dq + dV/dq + f(q, qd) = dp/dt - C(q, qd)^T qd + g(q) + f(q, qd),
/// (C^T qd = Mdot qd - C qd = dT/dq for the kinetic energy T = qd^T M qd / 2), linear in the
/// coefficients w of RobotDynamics::Features:
///   p = P(q, qd) w,      tau = d/dt [P w] + H(q, qd) w.
/// Here P = A(q, 0, qd) - A(q, 0, 0) (the features' part linear in qdd, evaluated at qdd := qd)
/// and H = A(q, qd, 0) - D_q[P(., qd)] qd, the directional derivative of P along qd (Mdot qd)
/// taken by central differences with a step of kDirectionalStep radians (or metres) of the
/// fastest joint: its relative error, the step squared times the third derivative, is below 1e-9
/// for links whose inertia varies on a scale of centimetres, far below any torque noise.
///
/// Filtering both sides by one causal filter F then gives rows without qdd:
///   F[tau] = F[d/dt (P w)] + F[H] w,
/// and F[d/dt P] is the filter applied to P's backward difference (momentum_rows.hpp), exact in
/// discrete time, so the filter adds no lag between the two sides.
#pragma once

#include <Eigen/Core>

#include "inertial/model/robot_dynamics.hpp"

namespace inertial {

/// [rad or m] the fastest joint's displacement in the central difference of P along qd.
inline constexpr double kDirectionalStep = 1e-5;

/// P and H of the file comment, allocation-free per sample after construction. Holds workspace
/// sized for one model, not the model itself (so its owner may move): every call takes the model.
class MomentumFeatures {
 public:
  explicit MomentumFeatures(const RobotDynamics& model);

  /// P(q, qd) and H(q, qd) into P and H (num_dofs x num_features each). No allocation, no
  /// exception. Preconditions (debug-asserted): sizes.
  /// Preconditions (debug-asserted): model is the one (or a copy of the one) constructed with.
  void Compute(const RobotDynamics& model, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
               Eigen::Ref<Eigen::MatrixXd> P, Eigen::Ref<Eigen::MatrixXd> H);

 private:
  // P(q, v) into out (A(q, 0, v) - A(q, 0, 0)), with scratch_ as the second term.
  void MomentumAt(const RobotDynamics& model, const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                  Eigen::Ref<Eigen::MatrixXd> out);

  TreeWorkspace workspace_;
  Eigen::VectorXd zero_, q_shifted_;
  Eigen::MatrixXd scratch_, plus_, minus_;
};

}  // namespace inertial
