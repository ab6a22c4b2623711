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
/// The honest spread of a held quantity. The posterior's curvature along what the data do not see
/// is gamma's, a number chosen for the optimizer (eq. 14), not what anyone knows of the link: on
/// the leg it gave a held mass +- 2 % while the truth was 40 % away. A held quantity therefore
/// reports at least the spread a CAD drawing's error gives it: theta relative to the URDF prior
/// distributed with independent stds kCadSpread (alpha 0.1: masses about 20 % off, std of log m =
/// 2 std alpha; stretches d and shears s 0.15: moments up to half off at 2 sigma; translations t
/// 0.2 rho0 per axis, rho0 = sqrt(tr(Sigma_c0) / m0) the prior's RMS radius: COMs off by centimetres,
/// a fraction of the link's size; plausibility.hpp's account of CAD errors), pushed through the
/// quantity's gradient: std >= sqrt(g^T diag(kCadSpread^2) g).
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
/// Correlated residuals and model error (issue 45). s^2 H^-1 assumes the residual is white noise.
/// On real logs it is neither white (torques low-passed before they are logged: the KUKA LWR4+
/// logs at 200 Hz were filtered at 2 Hz) nor only noise (effects the model lacks), and the
/// white-noise std then understates the estimate's real spread many times (KUKA run 1 against
/// run 2: friction and offset coefficients differing by up to 9.9 of their stds). Given the
/// data's statistics in contiguous time blocks (TimeBlocks, AccumulateTimeBlocks), the data's part
/// of the covariance is also estimated by a block ("batch means") sandwich, the estimator of
/// Newey & West (Econometrica 1987) with a flat kernel on non-overlapping blocks (Carlstein, Ann.
/// Stat. 1986; Conley, J. Econometrics 1999; the batch-means variance of Schmeiser, Oper. Res.
/// 1982):
///   C_data,block = H^-1 Omega H^-1,   Omega = c sum_k (g_k - (n_k/N) G)(g_k - (n_k/N) G)^T,
///   g_k = J_w^T (A_k^T A_k w - A_k^T tau_k)   (block k's score: its n_k samples' normal equations),
///   G = sum_k g_k,  c = K/(K-1) * N_rows/(N_rows - p_eff)
/// (centring: with a prior, G is the prior's pull, not 0; c corrects the centring's lost degree of
/// freedom and, as s^2 does, the fit's). A block's score sums its samples' scores, so whatever
/// correlation lies within a block, and a model error that varies slowly along the trajectory,
/// enter Omega as they enter the estimate; for white noise E Omega = sigma^2 H_data, and the
/// sandwich is the Laplace data part s^2 H^-1 H_data H^-1.
///
/// The reported variance of each quantity (gradient g, y = H^-1 g) is
///   v = s^2 y^T H_prior y + max(y^T Omega y, s^2 y^T H_data y),
/// i.e. the prior's part as before and the data's part never below the white-noise one: with K
/// blocks y^T Omega y is a sum of K squares, about sigma_q^2 chi^2_{K-1}/(K-1), low by chance by
/// 30 % or more in one quantity of ten for K = 20, and where the residual is white the Laplace
/// value is the better estimate of the same number. "Held by the prior" stays the white-noise
/// split (it compares the information the data and the prior carry, not the noise's colour).
/// `covariance` and `body_pi_covariance` are then C_white + (C_block - C_white)_+ (the two covariances
/// above, the positive part of their difference taken in the Jacobi-scaled coordinates), whose
/// quadratic forms are at least every quantity's v (a matrix cannot hold a per-quantity maximum).
///
/// The block rule (AccumulateTimeBlocks). The residual r = A w(x) - tau of each joint is measured
/// for its integrated autocorrelation time tau_int = 1 + 2 sum_{k=1}^{M} rho_k (samples; rho its
/// autocorrelation within the seam-free pieces, M the smallest lag with M >= 5 tau_int(M): Sokal's
/// automatic window, Sokal 1997 "Monte Carlo methods in statistical mechanics"), the largest over
/// the joints taken. Blocks are L = ceil(5 tau_int) samples long: for an exponentially correlated
/// residual (correlation time T, tau_int = 2T) a block's sum has variance n sigma^2 tau_int (1 -
/// tau_int/(2L)) to first order, so L = 5 tau_int biases Omega low by at most 10 % in variance (5 % in
/// std). K = N / L blocks estimate each variance with relative std sqrt(2/K); if L leaves fewer
/// than kMinTimeBlocks = 20 blocks, L is shortened to N / 20 (relative std of the variance
/// sqrt(2/20) = 0.32, 16 % in std): below that the estimate's own noise outweighs the bias the
/// shorter blocks add (and the max above caps the chance of a std far too low). A residual whose
/// correlation reaches across a large fraction of the log (a model error varying over the whole
/// trajectory) cannot be calibrated from one log at all; the blocks then catch the part that
/// varies on shorter scales. No block crosses a seam: rows more than 5 median steps apart (runs
/// laid end to end, recorded_runs.hpp, are a second or more apart; a log cut at a pause) start a
/// new piece, each piece split into round(n_piece / L) (at least 1) blocks of equal length.
///
/// Combinations of the coefficients (issue: "report what the data determine as what they
/// determine"). The regressor's coefficients w(x) = RobotDynamics::Coefficients(x) (pi of every
/// tree body, then payload blocks and effect coefficients) have, to first order, the covariance
///   C_w = J_w C_x J_w^T,   J_w = dw/dx,
/// and a linear combination k^T w (an identifiable base combination, identifiability.hpp) the
/// variance k^T C_w k. Its parts follow the quantities' rule above with the gradient g = J_w^T k:
/// v_prior = k^T C_w,prior k, the white-noise data part v_data = k^T C_w,data k, and with time
/// blocks the sandwich's data part v_block = k^T C_w,block k; the reported variance is
/// v_prior + max(v_data, v_block) (without blocks, k^T C_w k), and the combination is held by the
/// prior if v_prior > v_data. For a combination the data determine, v_prior is small (the prior
/// barely moves it), and the std is what the fit gives (no CAD floor: it is not a body quantity).
/// Undetermined: as for a body quantity, a combination whose gradient g = J_w^T k has a component
/// along the undetermined subspace (relative size above 1e-6, in the Jacobi-scaled coordinates:
/// ||Z^T D^-1/2 g|| > 1e-6 ||D^-1/2 g||, Z the subspace's orthonormal basis) has infinite std.
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

/// The std of each entry of theta (alpha, d1..d3, s12, s23, s13 dimensionless; t1..t3 as a fraction
/// of the prior's RMS radius) that a CAD drawing's error gives (file comment, "honest spread").
inline constexpr double kCadSpreadAlpha = 0.1, kCadSpreadShape = 0.15, kCadSpreadTranslation = 0.2;

/// The covariance of the regressor's coefficients w = model.Coefficients(x) (num_features square;
/// file comment, "Combinations"). Frozen bodies' and non-estimated bodies' coefficients are fixed
/// (rows and columns 0); the undetermined directions are left out, as in body_pi_covariance.
struct CoefficientCovariance {
  Eigen::MatrixXd total;       ///< C_w = J_w C J_w^T with C = FitUncertainty::covariance's finite part
  Eigen::MatrixXd data;        ///< the white-noise data part s^2 J_w H^-1 H_data H^-1 J_w^T
  Eigen::MatrixXd prior;       ///< the prior's part s^2 J_w H^-1 H_prior H^-1 J_w^T
  Eigen::MatrixXd block_data;  ///< the block sandwich's data part J_w H^-1 Omega H^-1 J_w^T (0 x 0 without blocks)
  /// For the undetermined test (file comment): J_w D^-1/2 Z, how w moves along each undetermined
  /// direction (columns; none when there is none), and J_w D^-1 J_w^T, whose quadratic form in k
  /// is ||D^-1/2 g||^2.
  Eigen::MatrixXd undetermined_moves;
  Eigen::MatrixXd scaled_gradient_gram;
  bool prior_acts = false;     ///< a prior was fitted (prior_weight > 0): "held" can be judged
};

/// A combination k^T w's uncertainty (file comment, "Combinations").
struct CombinationUncertainty {
  double std = 0;              ///< +infinity if it changes along an undetermined direction
  bool held_by_prior = false;  ///< the prior's share of its variance exceeds the data's
};

/// The uncertainty of a batch identification at its solution x (see the file comment).
struct FitUncertainty {
  double noise_sigma = 0;  ///< estimated torque noise std s = sqrt(data_cost / dof) [N m]
  /// With time blocks: how many, their length and the residual's correlation time [samples]; the
  /// largest ratio over the effect values and data-determined body quantities of the block
  /// sandwich's std to the white-noise one (1 without blocks; file comment).
  int time_blocks = 0;
  int block_length = 0;
  double correlation_time = 0;
  double max_block_to_white_ratio = 1;
  double dof = 0;          ///< residual degrees of freedom used: N_rows - effective_parameters
  double effective_parameters = 0;  ///< p_eff = trace(H^-1 H_data) (frozen bodies excluded)
  int undetermined_directions = 0;  ///< dimension of the undetermined subspace of H
  /// Covariance of x (P x P): s^2 H^-1 on the estimated parameters; rows and columns of frozen
  /// bodies are 0; a parameter with a component along an undetermined direction has +infinity on
  /// the diagonal and NaN (undefined) in the rest of its row and column.
  Eigen::MatrixXd covariance;
  /// Per estimated body (model.bodies() order), in its report frame; all 0 for a frozen body.
  std::vector<BodyUncertainty> bodies;
  /// The same stds without the CAD spread's floor on held quantities (file comment, "honest
  /// spread"): what the fit's curvature and residual alone give, for statistics that ask whether
  /// the data establish a departure (diagnosis/departure_margins.hpp).
  std::vector<BodyUncertainty> bodies_from_fit;
  /// Per estimated body (model.bodies() order): the covariance of pi in its report frame (first
  /// order; 0 for a frozen body; the undetermined directions left out, as in `covariance`).
  std::vector<Matrix10> body_pi_covariance;
  /// Per estimated body: which quantities the prior, not the data, determines.
  std::vector<BodyHeldByPrior> body_held;
  /// Per effect term (model.effects() order): the std of each RobotDynamics::EffectValues entry
  /// (b = e^s: std(b) = b std(s); offset c: std(c); spring {k = e^s, q0}).
  std::vector<std::vector<double>> effects;
  /// The covariance of the regressor's coefficients w and its parts (file comment, "Combinations").
  CoefficientCovariance coefficients;
};

/// The std of k^T w (k: one weight per coefficient of w, model.num_features()) and whether the
/// prior holds it (file comment, "Combinations"). @throws std::invalid_argument if k has the wrong
/// size or is not finite.
CombinationUncertainty UncertaintyOfCombination(const CoefficientCovariance& c, const Eigen::VectorXd& k);

/// The data's normal equations in contiguous time blocks (file comment, "The block rule").
struct TimeBlocks {
  std::vector<JointNormalEquations> blocks;  ///< one per block; their sum is the whole data's
  double correlation_time = 0;  ///< the residual's integrated autocorrelation time [samples], largest joint
  int block_length = 0;         ///< the target block length L [samples]
  int pieces = 0;               ///< seam-free pieces of the log (no block crosses a seam)
};

/// Fewer blocks than this estimate the sandwich's variances too noisily (file comment).
inline constexpr int kMinTimeBlocks = 20;

/// The residual's integrated autocorrelation time [samples] of one joint's residual series r over
/// the pieces [starts[i], starts[i+1]) (starts ends with r.size()), Sokal's window (file comment);
/// 1 for white noise, 1 where r is constant.
double IntegratedAutocorrelationTime(const Eigen::VectorXd& r, const std::vector<int>& starts);

/// The first row of every seam-free piece of `data` (a gap above 5 median steps starts one), then
/// data.size().
std::vector<int> SeamFreePieces(const JointSamples& data);

/// The blocks of `data` for the fit x: residual at x, its correlation time, block length, blocks'
/// normal equations (file comment). @throws std::invalid_argument if the samples do not match the
/// model, x is not the model's size, or there are fewer than 2 samples.
TimeBlocks AccumulateTimeBlocks(const RobotDynamics& model, const JointSamples& data, const Eigen::VectorXd& x);

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

/// The same with the data's part also from the block sandwich of `blocks` (file comment: each
/// variance the larger of it and the white-noise one). `blocks` sum to `data` (the caller's
/// AccumulateTimeBlocks of the same samples), or to a part of it: an online fit restored from a
/// checkpoint has blocks only of the samples since (online_fit.hpp); Omega is then scaled by
/// N / N_blocks, the blocks' spread taken as that of every sample. Fewer than 2 blocks give the
/// white-noise result.
/// @throws as above, and std::invalid_argument if a block does not match the model's features.
FitUncertainty EstimateFitUncertainty(const RobotDynamics& model, const JointNormalEquations& data,
                                      const Eigen::VectorXd& x, double prior_weight,
                                      const std::vector<bool>& frozen_bodies, const TimeBlocks& blocks);

}  // namespace inertial
