/// @file covariance_uncertainty.hpp
/// How sure a running estimate is, from the covariance its recursive estimator keeps (the Kalman
/// filters, recursive least squares; online/): first-order standard deviations of every estimated
/// body's mass, COM and inertia and of every effect coefficient. The batch fit's uncertainty, with
/// its noise estimated from the residual and its "held by the prior", is fit_uncertainty.hpp's; a
/// running estimator's covariance has no residual-based noise and no prior split, so nothing here
/// is labelled held.
///
/// Method (first order, the delta method): a quantity phi(x) of the parameters x with covariance P
/// has variance g^T P g, g = d phi / d x at the estimate.
///  - Parameters x of RobotDynamics (log-Cholesky theta relative to each prior, effect parameters
///    s with b = e^s): body e's pi in its report frame is L pi(theta_e) (ReportFrameMap, exact), so
///    its covariance is L J P_ee J^T L^T with J = d pi / d theta_e; mass, COM and inertia follow
///    through UncertaintyOf. Effects: b = e^s gives std(b) = b std(s) (each of an asymmetric
///    form's two); an offset c = s, std(c) = std(s); a spring {k = e^s, q0} gives k's as b's and
///    q0's std(q0) directly.
///  - Coefficients (linear = true: x is w, as linear RLS keeps it): each tree body's pi is w's
///    block directly (a payload or rotor inside its tree body's block: every estimated body on a
///    tree body reports that block, its covariance the block of P); an effect's coefficients are
///    w's own; a spring's w = [k, k q0] gives q0 = w1 / w0 and g = [-w1 / w0^2, 1 / w0].
/// A body whose estimated mass is not positive has no standard deviations (all 0, as UncertaintyOf
/// needs a mass).
///
/// Conventions: SI units; pi order of types.hpp; effect values in RobotDynamics::EffectValues order.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "inertial/estimation/parameter_layout.hpp"
#include "inertial/model/robot_dynamics.hpp"

namespace inertial {

struct CovarianceUncertainty {
  /// Per estimated body (model.bodies() order): its estimate (report frame; linear: its tree
  /// body's pi), the covariance of that pi, and its standard deviations.
  std::vector<InertialParams> bodies;
  std::vector<Matrix10> body_pi_covariance;
  std::vector<BodyUncertainty> body_stds;
  /// Per effect term (model.effects() order): the std of each RobotDynamics::EffectValues entry.
  std::vector<std::vector<double>> effects;
};

/// The standard deviations of the estimate x with covariance P (see the file comment).
/// @param linear x is w (the coefficients), not RobotDynamics's parameters.
/// @throws std::invalid_argument if x does not have the model's size (parameters, or features
/// when linear) or P is not x.size() square.
CovarianceUncertainty UncertaintyFromCovariance(const RobotDynamics& model, const Eigen::VectorXd& x,
                                                const Eigen::MatrixXd& P, bool linear);

}  // namespace inertial
