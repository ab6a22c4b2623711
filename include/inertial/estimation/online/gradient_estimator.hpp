/// @file gradient_estimator.hpp
/// The natural gradient (adaptive) law of the log-det divergence: every estimate a consistent body,
/// no covariance, no solve, one gain for all links.
///
/// **The objective.** The law descends the least-squares objective of every sample so far,
/// L(w) = sum_k |y_k - A_k w|^2 / 2 = w^T S w / 2 - s^T w + const, kept as its statistics
/// S = sum A^T A, s = sum A^T y (the integral of the regressor of Slotine and Li's composite
/// adaptation, "Composite adaptive control of robot manipulators", Automatica 1989): the one
/// objective identify and the online fit minimize, without their prior. A law on each sample's own
/// error alone (a normalized LMS) fits the last few samples and wanders along what they do not
/// excite: measured 10-82 times the batch fit's held-out error on the bundled robots, Euclidean or
/// natural, at any gain (docs/online.md).
///
/// **The law.** Each body's pseudo-inertia J (4 x 4, positive definite) moves along the natural
/// gradient of L in the geometry of the log-det (Bregman) divergence
/// d(J' || J) = tr(J^-1 J') - log det(J^-1 J') - 4, whose Hessian at J is the metric
/// <X, Y>_J = tr(J^-1 X J^-1 Y) (Lee, Kwon and Park, "A natural adaptive control law for robot
/// manipulators", IROS 2018; Wensing and Slotine, "Beyond convexity", PLoS ONE 2020). With
/// G = dL/dJ = -T*(g_b) (g = s - S w, T* = PseudoInertiaGradient), the natural gradient is J G J
/// and the continuous law reads d(J^-1)/dt = gamma G. It is discretized on the manifold by the
/// exponential map of that metric,
///
///   J+ = J^1/2 expm(-gamma J^1/2 G J^1/2) J^1/2 = F expm(gamma S_b) F^T,  S_b = F^T T*(g_b) F,
///
/// for any factor J = F F^T (here F = U U0, the log-Cholesky factor times the prior's; another
/// factor F Q, Q orthogonal, gives the same J+). J+ is positive definite exactly, whatever the
/// step; to first order J+ = J - gamma J G J. theta+ follows from J+ (FromPi). Effect parameters
/// (friction, offsets, springs ...) take the step dx = gamma Gamma (dw/dx)^T g on their own x
/// (Gamma = diag(scale^2)); for an exponentially mapped coefficient c = e^x with unit scale this is
/// the natural gradient of the log barrier -log c, the scalar analogue of -log det J. The law
/// takes no prior: with few samples the minimizer of L itself is loosely determined along what
/// they do not excite, and the estimate goes there (the online fit's solve holds those directions
/// at the prior).
///
/// **The step.** One step per sample along conjugate directions: d = z + beta d_prev, z the
/// natural gradient above (preconditioned conjugate gradients, Polak-Ribiere+ with
/// beta = max(0, z . (g - g_prev) / (z_prev . g_prev)), which restarts along z whenever the
/// objective's change spoils conjugacy), of length gamma = gain (g . dw) / (dw^T S dw), dw the
/// first-order change of w along d: gain 1 is the exact minimizer of the quadratic along d, as
/// conjugate gradients need, and (0, 2) decreases L to first order. In J the direction is
/// D_b = J(dw_b) (pi and J are one to one) and the step J+ = F expm(gamma F^-1 D_b F^-T) F^T,
/// which is the formula above when beta = 0. Steepest descent alone zig-zags on the
/// ill-conditioned objective of a robot: measured held-out error over the batch fit's on the
/// bundled robots and the KUKA, 1.04-1.98x with exact steps, 1.07-1.31x relaxed to half of them,
/// 1.00-1.18x with conjugate directions (docs/online.md).
///
/// Outliers are gated on |r| / (sigma sqrt(m)) of the sample's prediction error, as in the Kalman
/// update (Huber weights beyond `huber` on its statistics); steps are bounded (|gamma S_b|_F per
/// body, the relative change of its J, and |gamma dx|_inf). Cost per sample: the statistics'
/// rank-m update, O(F^2 m), as the online fit's. Allocation-free and exception-free after
/// construction; a sample it refuses leaves estimate and statistics as they were.
#pragma once

#include <vector>

#include "inertial/estimation/parameter_layout.hpp"
#include "inertial/estimation/online/recursive_estimator.hpp"

namespace inertial {

struct GradientOptions {
  /// The step over the exact minimizer of the objective along the law's direction, in (0, 2):
  /// 1, the exact line search conjugate directions need (see the file comment).
  double gain = 1.0;
  double measurement_sigma = 1.0;  ///< standard deviation of each measurement (for the gate)
  double huber = 3.0;              ///< normalized residual (sigmas) where down-weighting starts
  double gate = 30.0;              ///< normalized residual (sigmas) beyond which a sample is an outlier
  int max_consecutive_outliers = 50;
  /// Bound on a step: |gamma S_b|_F per body (the relative change of its J, 0.1 = 10 %) and
  /// |dx|_inf of the effect parameters.
  double max_step = 0.1;
  double max_abs_parameter = 50.0;
  /// Bodies the law holds where they are (e.g. links known from CAD while a payload is learned),
  /// by the layout's body index; empty: none. Their statistics are kept all the same.
  std::vector<bool> frozen_bodies;
};

class GradientEstimator final : public RecursiveEstimator {
 public:
  /// @param scale per-parameter adaptation scale of the effect parameters (Gamma = diag(scale^2));
  /// its entries over the bodies are not used (the metric there is the log-det divergence's).
  /// The state (State()) carries the statistics [S s; s^T 0] (EstimatorState::statistics) and the
  /// last direction (EstimatorState::directions).
  /// @throws std::invalid_argument for wrong sizes, non-finite values or bad options.
  GradientEstimator(ParameterLayout layout, int num_measurements, const Eigen::VectorXd& x0,
                    const Eigen::VectorXd& scale, const GradientOptions& options = {});

  std::string_view kind() const override { return "gradient"; }
  const Eigen::VectorXd& parameters() const override { return x_; }
  void Coefficients(Eigen::Ref<Eigen::VectorXd> w) const override { layout_.Coefficients(x_, w); }
  Eigen::MatrixXd Covariance() const override { return Eigen::MatrixXd(); }
  /// Runs of more than max_consecutive_outliers outliers taken as changes (the memory restarted).
  std::uint64_t changes_detected() const override { return changes_; }
  const ParameterLayout& layout() const { return layout_; }

 protected:
  UpdateStatus Apply(const Eigen::MatrixXd& A, const Eigen::VectorXd& y) override;
  bool SetParameters(const Eigen::VectorXd& x, const Eigen::MatrixXd& P, std::string* why) override;
  void SaveExtra(EstimatorState* state) const override;
  bool CheckExtra(const EstimatorState& state, std::string* why) const override;
  void RestoreExtra(const EstimatorState& state) override;

 private:
  int DirectionsSize() const;  // of EstimatorState::directions

  ParameterLayout layout_;
  GradientOptions options_;
  int padded_ = 0;  // F rounded up to the kernels' block (symmetric_rank_update.hpp)
  Eigen::VectorXd x_, gamma_, w_, r_, dw_, dx_, x_next_;
  Eigen::MatrixXd S_, At_;                  // the memory's A^T A (lower triangle, padded), A^T of a sample
  Eigen::VectorXd s_, ones_, g_, wp_, Sdw_, direction_;
  std::vector<Matrix4> reference_factor_;   // U0 of each body's prior (J0 = U0 U0^T)
  std::vector<Matrix4> factor_, exponent_;  // F and S_b of each body, this sample
  int consecutive_outliers_ = 0;
  std::uint64_t changes_ = 0;
  std::vector<Matrix4> direction_z_, direction_d_, previous_d_;  // per body, in J: z, d, the last d
  Eigen::VectorXd Adw_;
  Eigen::VectorXd previous_g_, previous_dw_, previous_dx_;
  double previous_zg_ = 0.0;
  bool has_previous_ = false;
};

}  // namespace inertial
