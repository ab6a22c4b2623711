/// @file fit_uncertainty.hpp
/// Uncertainty of the batch identification (IdentifyJointModel, joint_identification.hpp): standard
/// deviations of every estimated body's mass, COM and inertia and of every effect coefficient, and
/// which body quantities the prior, not the data, determines.
///
/// Method. The fit minimizes the paper's regularized cost (eq. 14), written as
///   F(x) = 0.5 (||A w(x) - tau||^2 + gamma sum_b ||r_b(theta_b)||^2),
/// with d_b = ||r_b||^2 the log-det divergence to body b's prior (log_det_divergence.hpp). Read as a
/// negative log posterior over sigma^2 (Gaussian torque noise of variance sigma^2, prior density
/// proportional to exp(-gamma d_b / (2 sigma^2))), its Laplace approximation at the minimum x is
///   x ~ N(x, s^2 H^-1),   H = H_data + H_prior,
///   H_data = J_w^T A^T A J_w,   H_prior = blockdiag_b(gamma J_r,b^T J_r,b)
/// (the Gauss-Newton Hessian of F, as IdentifyJointModel forms it with newton = false; J_w = dw/dx,
/// J_r,b = dr_b/dtheta_b; always positive semi-definite). The noise variance is estimated from the residual:
///   s^2 = ||A w(x) - tau||^2 / (N_rows - p_eff),   N_rows = num_samples * num_dofs,
///   p_eff = trace(H^-1 H_data),
/// the effective number of parameters of a regularized fit (the trace of its hat matrix: a
/// parameter the data fix counts 1, one the prior holds counts ~0; p_eff = P without a prior).
/// Frozen bodies are fixed, not estimated: their parameters are left out of H (the others are
/// conditioned on them), and their standard deviations are 0.
///
/// Undetermined directions. H is Jacobi-scaled (D^-1/2 H D^-1/2, D = diag(H), so that the units of
/// the parameters do not matter) and eigen-decomposed; eigenvalues below 1e-12 of the largest span
/// the directions neither the data nor the prior determine (only possible without a prior, or for
/// effect parameters). H^-1 above is the pseudo-inverse on the other directions; a quantity whose
/// gradient has a component along an undetermined direction (relative size above 1e-6) has
/// standard deviation +infinity.
///
/// Body quantities (first order): pi of body e in its report frame (EstimatedBody::report_frame,
/// as RobotDynamics::BodyInertia) is L pi_tree(theta_e) with L linear, so its covariance is
/// J C_theta J^T with J = L J_pi_theta; mass, COM and inertia follow through UncertaintyOf
/// (parameter_layout.hpp).
///
/// "Held by the prior". The posterior covariance splits exactly into a part due to the torque noise
/// and a part due to the prior: H^-1 = H^-1 H_data H^-1 + H^-1 H_prior H^-1. For a scalar body
/// quantity phi with gradient g (with respect to x) and y = H^-1 g,
///   v_post = s^2 g^T H^-1 g = s^2 y^T H_data y + s^2 y^T H_prior y = v_data + v_prior,
/// and phi is held by the prior if v_prior > v_data (the prior's share of its variance exceeds one
/// half). For a single scalar Gaussian this is v_post > 0.5 v_prior,alone with v_prior,alone =
/// s^2 / I_prior (v_post / v_prior,alone = I_prior / (I_prior + I_data)), i.e. the data carry less
/// information about phi than the prior. The split is used instead of that comparison because
/// the prior correlates a body's parameters: a quantity no torque depends on (the mass of a link
/// turning about a fixed axis) can have v_post far below its prior-alone variance because the
/// data fix the quantities the prior ties it to, yet its variance still comes from the prior.
/// v_data is also the variance of the estimate over repeated noise draws (first order), so for a
/// quantity not held, the reported std overstates that spread by at most sqrt(2) (to first order
/// and with the exact Hessian; see Accuracy). Effects have
/// no prior and are never held; neither is a quantity with infinite std (nothing holds it).
///
/// Accuracy (tests/formats/fit_uncertainty_monte_carlo_test.cpp, 100 noise draws on the bundled leg):
/// for quantities not held, the spread of the estimates over noise draws is 0.5 - 1.1 times the
/// reported std. Gauss-Newton drops the curvature terms weighted by the residuals, which do not
/// vanish when the prior pulls the fit away from the data (sum_k grad_w_k d2w_k/dx2 and
/// gamma sum_i r_i d2r_i/dtheta2): against the exact Hessian it gave stds within 10 % for
/// data-determined quantities, up to 1.4 times larger near the held threshold and up to 2.5 times
/// larger for held ones (conservative). A held quantity's std is the prior's spread, not an error
/// bound against the truth: when the prior is wrong the estimate is biased by more than that.
///
/// Conventions: SI units; pi and mci orders of types.hpp and parameter_layout.hpp.
#pragma once

#include <array>
#include <vector>

#include "inertial/estimation/batch/joint_identification.hpp"
#include "inertial/estimation/parameter_layout.hpp"

namespace inertial {

/// Which quantities of one estimated body the prior, not the data, determines (see the file
/// comment). com and inertia_about_com in the body's report frame, inertia entries in the order
/// Ixx Iyy Izz Ixy Iyz Ixz. All false for a frozen body and without a prior (gamma = 0).
struct BodyHeldByPrior {
  bool mass = false;
  std::array<bool, 3> com{};
  std::array<bool, 6> inertia_about_com{};
};

/// The uncertainty of a batch identification at its solution x (see the file comment).
struct FitUncertainty {
  double noise_sigma = 0;  ///< estimated torque noise std s = sqrt(data_cost / dof) [N m]
  double dof = 0;          ///< residual degrees of freedom used: N_rows - effective_parameters
  double effective_parameters = 0;  ///< p_eff = trace(H^-1 H_data) (frozen bodies excluded)
  int undetermined_directions = 0;  ///< dimension of the undetermined subspace of H
  /// Covariance of x (P x P): s^2 H^-1 on the estimated parameters; rows and columns of frozen
  /// bodies are 0; a parameter with a component along an undetermined direction has +infinity on
  /// the diagonal and NaN (undefined) in the rest of its row and column.
  Eigen::MatrixXd covariance;
  /// Per estimated body (model.bodies() order), in its report frame; all 0 for a frozen body.
  std::vector<BodyUncertainty> bodies;
  /// Per estimated body (model.bodies() order): the covariance of pi in its report frame (first
  /// order; 0 for a frozen body; the undetermined directions left out, as in `covariance`).
  std::vector<Matrix10> body_pi_covariance;
  /// Per estimated body: which quantities the prior, not the data, determines.
  std::vector<BodyHeldByPrior> body_held;
  /// Per effect term (model.effects() order): the std of each RobotDynamics::EffectValues entry
  /// (b = e^s: std(b) = b std(s); offset c: std(c); spring {k = e^s, q0}).
  std::vector<std::vector<double>> effects;
};

/// The linear map L from a body's pi in its tree body's frame to its pi in its report frame
/// (EstimatedBody::report_frame): RobotDynamics::BodyInertia(e, x) = L pi_tree(theta_e), so a
/// covariance C of pi_tree becomes L C L^T (10 x 10, exact: pi moves linearly under a rigid
/// transform, J_A = T J_B T^T).
Matrix10 ReportFrameMap(const EstimatedBody& body);

/// The uncertainty of the fit x of IdentifyJointModel(model, data, {prior_weight, frozen_bodies}).
/// x should be that fit's minimum (the Laplace approximation is taken there); frozen bodies' theta
/// are taken as they are in x.
/// @throws std::invalid_argument if data, x or frozen_bodies do not match the model, x is not
/// finite, prior_weight is negative or not finite, or there are no more torque rows than effective
/// parameters (no residual degrees of freedom).
FitUncertainty EstimateFitUncertainty(const RobotDynamics& model, const JointNormalEquations& data,
                                      const Eigen::VectorXd& x, double prior_weight,
                                      const std::vector<bool>& frozen_bodies = {});

}  // namespace inertial
