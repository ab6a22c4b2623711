/// @file online_fit.hpp
/// The online schedule of the batch fit: per sample, the sufficient statistics of the objective
/// that `identify` minimizes (IdentifyJointModel, joint_identification.hpp; the paper's eq. 14),
///
///   F(x) = 0.5 ( sum_i lambda_i ||A_i w(x) - tau_i||^2 + gamma sum_b d(J_b(theta_b) || J_b,prior) ),
///
/// and, every so often and off the tick, the solve of that objective from them. Because
/// tau = A w is linear in the coefficients w, the data enter F only through
///   S = sum_i lambda_i A_i^T A_i,   s = sum_i lambda_i A_i^T tau_i,   c = sum_i lambda_i tau_i^T tau_i
/// (lambda_i = exp(-(t_now - t_i) / T) with forgetting time T; 1 without forgetting). So the
/// estimate after a Solve() IS the batch fit of the samples kept so far, with the same start
/// (DefaultInitialParameters: effects at their least-squares values, not at 1 in SI units), the
/// same Levenberg-Marquardt, the same prior weight, and the same Laplace uncertainty
/// (fit_uncertainty.hpp, with "held by the prior"). Nothing locks onto early linearization points,
/// as an extended Kalman filter on x does: each solve re-linearizes over all the data.
///
/// The tick (Update) costs one symmetric rank-m update of S (m = DOFs; the forgetting factor is
/// applied in the same pass, symmetric_rank_update.hpp), the gate's C_w A^T (the span product of
/// symmetric_span_product.hpp), and products of m x F: O(m F^2), no allocation, no exception. The solve costs a few
/// Levenberg-Marquardt iterations of O(P^3) (P parameters), independent of the number of samples;
/// it runs when the caller asks (Solve(), or Snapshot() -> SolveOnlineFit() on another thread ->
/// Adopt()). solve_due() says when the statistics have grown enough since the last solve.
///
/// Robust weights and the noise. identify leaves out rows whose residual is more than k robust
/// standard deviations from the column's median (robust_identification.hpp). Online, each sample is
/// judged once, when it arrives, against the last solve: its prediction error r_j is refused
/// (UpdateStatus::kOutlier, not added to the statistics) if |r_j - m_j| > k sqrt(s_j^2 + v_j) for
/// any joint j, with m_j = 0 and s_j = 1.4826 median |r_j| over the last `noise_window` prediction
/// errors of joint j (the per-joint noise, found from the data: nothing to tell), floored as
/// identify floors them (1e-3 of the RMS of the joint's torque over the window, 1e-9);
/// v_j = a_j^T C_w a_j the variance the estimate's own uncertainty adds to the prediction (C_w the
/// Laplace covariance of w at the last solve: a fit of few samples extrapolates, and its
/// prediction errors on what it has not seen are not glitches); and k = DefaultOutlierThreshold
/// of the residuals seen so far (identify's k for a log of that length). A refused sample is not
/// dropped at once: it is held (UpdateStatus::kBuffered) until the next solve, which fits the
/// statistics with the held samples, judges each against that fit (as identify's rounds re-judge
/// every row against the fit of the kept ones), and refits without those still out: a fit of few
/// samples mispredicts the first velocity reversal or a new region of the workspace, and those
/// samples are data, not glitches. The first `warmup` samples are held the same way until the
/// first solve gives a noise scale.
///
/// Standard deviations that cover the truth (issue 45; fit_uncertainty.hpp, "Correlated residuals
/// and model error"). identify takes the data's part of the covariance also from a block sandwich
/// over time blocks of its log. The online fit keeps the same blocks without keeping samples: the
/// statistics are cumulative sums, so a block's normal equations are the difference of the sums at
/// its two ends. At each block's end the tick copies the sums into one of kMaxTimeBlocks + 1
/// preallocated slots (one F x F copy, no allocation); a block ends when it holds
/// max(kMinBlockSamples, N / kTargetTimeBlocks) samples, so the blocks grow with the stream, and
/// when the slots are full the two neighbours with the fewest samples together are merged by
/// dropping their common end (slots swapped, nothing copied): 32 to 40 blocks of roughly equal
/// length N / 32 once N >= 160, in the stream's order. The differences are formed by Snapshot(),
/// off the tick. identify's rule is ceil(5 tau_int) samples with at least kMinTimeBlocks = 20
/// blocks; N / 32 is shorter than its floor N / 20 (a little more of a long correlation missed,
/// sqrt(2/32) instead of sqrt(2/20) relative noise in each variance), and needs no residual
/// series, which the online fit does not keep; so no correlation time is reported. The solve
/// passes the blocks (the open one with the held samples it kept) to EstimateFitUncertainty, used
/// once there are kMinTimeBlocks of them. After a restore from a checkpoint (which keeps only the
/// sums) the blocks cover the samples since, and Omega is scaled to the whole
/// (fit_uncertainty.hpp); with forgetting (a finite T) samples decay within a block and no blocks
/// are kept: the stds are the white-noise ones.
///
/// A change of the system (a payload picked up): more than `max_consecutive_outliers` samples in a
/// row refused, and a solve that included the run's held samples refused them too. The statistics
/// are then emptied and the estimator starts over from its current estimate, warm-up included (the
/// old samples describe another body). A run no solve has judged yet is a solver that fell behind
/// (inertiald's solver thread on a loaded machine): the statistics stay, and the samples that find
/// no room among the held ones meanwhile are refused (kOutlier).
///
/// Conventions: SI units; joint rows in the model's DOF order.
#pragma once

#include <cstdint>
#include <limits>

#include <memory>
#include <vector>

#include "inertial/estimation/fit_uncertainty.hpp"
#include "inertial/estimation/batch/joint_identification.hpp"
#include "inertial/estimation/online/recursive_estimator.hpp"
#include "inertial/model/robot_dynamics.hpp"

namespace inertial {

struct OnlineFitOptions {
  /// T [s]: a sample's weight decays as exp(-age / T). Infinity (the default): every sample counts
  /// fully, and the estimate is the batch fit of the whole stream.
  double forgetting_time = std::numeric_limits<double>::infinity();
  /// k of the gate in robust standard deviations; 0: DefaultOutlierThreshold (identify's).
  double gate = 0.0;
  /// Prediction errors per joint the noise scale is taken over: 500 samples (1 s at 500 Hz, 0.5 s
  /// at 1 kHz) give the MAD to about 5 % (its relative standard error is ~1.1 / sqrt(n) for
  /// Gaussian residuals), while still following a noise that changes within seconds.
  int noise_window = 500;
  /// Samples buffered before the first solve. 32 samples of m joints give 32 m residuals for the
  /// first noise scale (a MAD within ~20 %); a gate of k ~ 14 scales is insensitive to that.
  int warmup = 32;
  /// More refused samples than this in a row: the system changed (the statistics are emptied).
  /// 50, as the Kalman estimators' change detector (kalman_update.hpp): 0.1 s at 500 Hz, and with
  /// k chosen so that 0.01 good residuals are refused in a whole log, 50 in a row never happen by
  /// chance.
  int max_consecutive_outliers = 50;
  /// The statistics are re-solved once they have grown by this fraction since the last solve
  /// (solve_due()). The change of the estimate from N to N (1 + f) samples is ~f / (1 + f) of its
  /// remaining error, so 1/8 keeps the estimate within ~11 % of the fit of every sample so far for
  /// ~9 solves per doubling of the data (with forgetting, of the effective count ~ T x rate).
  double solve_growth = 0.125;
  /// The solve: identify's options (LM, damped Newton, bodies held at their priors); its `initial` is unused.
  JointIdentificationOptions solve;
};

/// What a solve needs, copied from the estimator (Snapshot()), so that it can run on another thread.
struct OnlineFitSnapshot {
  JointNormalEquations equations;  ///< of the accepted samples, normalized so the newest weighs 1
  Eigen::VectorXd x;               ///< the current estimate (the warm start once solved)
  bool solved = false;             ///< false: start from DefaultInitialParameters, as identify
  Eigen::MatrixXd pending_rows;    ///< the held samples' A^T (m columns each): F x (m count)
  Eigen::MatrixXd pending_y;       ///< m x count
  Eigen::MatrixXd window_r;        ///< m x count: recent prediction errors
  Eigen::MatrixXd window_y;        ///< m x count: their measured torques
  long long residuals_seen = 0;    ///< rows x joints judged so far (for k)
  /// The time blocks of the accepted samples (the last one the block still open; none with
  /// forgetting; after a restore, of the samples since): file comment.
  std::vector<JointNormalEquations> blocks;
  std::uint64_t generation = 0;    ///< increments when the statistics are emptied
};

struct OnlineFitSolution {
  Eigen::VectorXd x;
  Eigen::VectorXd noise;   ///< per joint s_j (floored) [N m or N]
  Eigen::VectorXd center;  ///< per joint m_j
  double gate = 0.0;       ///< k
  std::vector<bool> pending_kept;  ///< per held sample: within the gate of the fit that includes it
  Eigen::MatrixXd prediction_covariance;  ///< C_w (F x F) of the coefficients at x (the gate's)
  /// The Laplace uncertainty at x (EstimateFitUncertainty of the statistics solved), or null before
  /// there are residual degrees of freedom.
  std::shared_ptr<const FitUncertainty> uncertainty;
  DenseLevenbergMarquardtResult lm;
  std::uint64_t generation = 0;
};

/// The solve of a snapshot (allocates; any thread). @throws std::invalid_argument as
/// IdentifyJointModel for options that do not fit the model.
OnlineFitSolution SolveOnlineFit(const RobotDynamics& model, const OnlineFitSnapshot& snapshot,
                                 const OnlineFitOptions& options);

/// Time blocks kept for the sandwich covariance (file comment, "Standard deviations"); a block
/// holds at least kMinBlockSamples: five times a white residual's correlation time (1 sample),
/// identify's shortest block, which also bounds how often the tick copies the sums early on.
inline constexpr int kMaxTimeBlocks = 40, kTargetTimeBlocks = 32;
inline constexpr double kMinBlockSamples = 5.0;

class OnlineFit final : public RecursiveEstimator {
 public:
  /// @param x0 the estimate until the first solve (zeros: the URDF's priors).
  /// @throws std::invalid_argument for a wrong-size or non-finite x0 or options out of range.
  OnlineFit(RobotDynamics model, const Eigen::VectorXd& x0, const OnlineFitOptions& options = {});

  std::string_view kind() const override { return "gauss_newton"; }
  const Eigen::VectorXd& parameters() const override { return x_; }
  void Coefficients(Eigen::Ref<Eigen::VectorXd> w) const override { w = w_; }
  /// The Laplace covariance of the batch objective at x (EstimateFitUncertainty; allocates). Empty
  /// before any sample; entries along undetermined directions are infinite.
  Eigen::MatrixXd Covariance() const override;
  std::uint64_t changes_detected() const override { return changes_; }

  /// The statistics have grown by options.solve_growth since the last solve (or the warm-up is full).
  bool solve_due() const;
  /// Snapshot -> SolveOnlineFit -> Adopt, whether due or not. Allocates; call it off the tick.
  /// Warm-started from the current estimate, or with from_start from identify's own start
  /// (DefaultInitialParameters): the objective's valleys along what only the prior holds are so
  /// flat that Levenberg-Marquardt stops at points that differ there by the prior's spread
  /// depending on where it began (identify itself takes 200-300 iterations on the leg); the final
  /// estimate of a log is solved from identify's start so that it is identify's fit, digit for digit.
  /// Returns false (the estimate unchanged) if no sample has been accepted yet or the solve failed
  /// numerically.
  bool Solve(bool from_start = false);
  OnlineFitSnapshot Snapshot() const;
  /// Takes a solution of Snapshot(): the estimate, the noise and gate, the warm-up samples within
  /// it. A solution of statistics since emptied (a change) gives only its x as the next start.
  /// Returns false if it is not finite.
  bool Adopt(const OnlineFitSolution& solution);

  const RobotDynamics& model() const { return model_; }
  const OnlineFitOptions& options() const { return options_; }
  /// The normalized statistics (allocates).
  JointNormalEquations Equations() const;
  /// The uncertainty computed by the last solve adopted (null before one): what reports read
  /// without recomputing it (an O(P^3) eigen-decomposition) under the estimator's lock.
  const std::shared_ptr<const FitUncertainty>& uncertainty() const { return uncertainty_; }
  /// Held samples resolved by solves so far: kept and refused (counted buffered until then).
  std::uint64_t held_kept() const { return held_kept_; }
  std::uint64_t held_refused() const { return held_refused_; }
  /// Per-joint noise scale s_j of the last solve (zeros before it) [N m or N].
  const Eigen::VectorXd& noise() const { return noise_; }
  /// Per joint, the gate's scale for the last sample judged: sqrt(s_j^2 + a_j^T C_w a_j), the noise
  /// plus the variance the estimate's uncertainty adds to that sample's prediction (zeros before
  /// the first solve) [N m or N].
  const Eigen::VectorXd& prediction_scale() const { return gate_scale_; }
  bool solved() const { return solved_; }
  int solves() const { return solves_; }
  /// Samples in the statistics (weighted by forgetting: their effective number).
  double effective_samples() const { return weight_; }

  /// The statistics as one (F+1) x (F+1) symmetric matrix [S s; s^T c]: what a checkpoint keeps
  /// (EstimatorState::statistics, with the effective sample count).
  Eigen::MatrixXd StatisticsMatrix() const;

 protected:
  UpdateStatus Apply(const Eigen::MatrixXd& A, const Eigen::VectorXd& y) override;
  bool SetParameters(const Eigen::VectorXd& x, const Eigen::MatrixXd& P, std::string* why) override;
  Eigen::MatrixXd StateCovariance() const override { return {}; }
  void SaveExtra(EstimatorState* state) const override;
  bool CheckExtra(const EstimatorState& state, std::string* why) const override;
  void RestoreExtra(const EstimatorState& state) override;

 private:
  /// The sample in At_ (LoadRows) with its measurements y joins the statistics at weight 1, the
  /// rest decayed by lambda.
  void Accumulate(const Eigen::VectorXd& y, double lambda);
  /// At_'s first m columns = rows (columns of rows_t, F x m) sorted by where they begin, with their
  /// spans first_, end_ and the order order_ (At_'s column k is row order_[k]).
  void LoadRows(const Eigen::Ref<const Eigen::MatrixXd>& rows_t);
  void AddAtToS();     ///< S += A^T A over the spans (unit weight)
  void Empty();
  /// `place`: the sample's place in the current run of refusals (1, 2, ...), 0 outside one.
  void Hold(const Eigen::MatrixXd& A, const Eigen::VectorXd& y, int place = 0);
  void ResolveHeld(bool kept);
  void EndBlockIfDue();
  void ResetBlocks();
  std::vector<JointNormalEquations> Blocks() const;  ///< closed ones and the open one (allocates)

  RobotDynamics model_;
  OnlineFitOptions options_;
  int m_, F_, Fp_;
  Eigen::VectorXd x_, w_;
  Eigen::MatrixXd S_;       ///< lower triangle, Fp x Fp (padded to kSpanBlock)
  Eigen::VectorXd s_;
  double c_ = 0.0, weight_ = 0.0;
  Eigen::MatrixXd At_;      ///< Fp x mp: A^T padded (rows to kSpanBlock, columns to kSpanBlock)
  Eigen::MatrixXd Cw_, CwAt_;  ///< the gate's C_w (lower triangle, padded) and C_w A^T
  Eigen::VectorXd gate_scale_;
  /// A's rows sorted by the first of their nonzero columns [first, end) (a robot's regressor is
  /// block-triangular: a joint's row is zero over the bodies before it; a zero row sorts last with
  /// first = end = Fp): the products run over the spans alone (symmetric_span_product.hpp).
  Eigen::MatrixXd Ar_;      ///< F x m: A^T as given
  Eigen::VectorXd ys_;      ///< y in At_'s column order
  std::vector<int> order_, first_, end_;
  Eigen::VectorXd ones_, d_, r_;
  /// Samples held for the next solve: the warm-up, and those the gate refused since the last solve.
  Eigen::MatrixXd pending_rows_, pending_y_;
  int pending_count_ = 0, capacity_ = 0;
  static constexpr int kPendingSolve = 4;
  Eigen::MatrixXd window_r_, window_y_;
  int window_count_ = 0, window_next_ = 0;
  Eigen::VectorXd noise_, center_;
  double gate_ = 0.0;
  bool solved_ = false, has_scale_ = false;
  double added_since_solve_ = 0.0;  ///< weight added since the last solve, decayed as the rest
  std::shared_ptr<const FitUncertainty> uncertainty_;
  /// Time blocks (file comment): the sums (S's lower triangle F x F, s, c, the sample count) at
  /// the blocks' ends; entry 0 is where the blocks start (zero, or a restored checkpoint's sums),
  /// entries 1..ends_ the closed blocks' ends, block k the difference of ends k and k - 1.
  std::vector<Eigen::MatrixXd> ends_S_;
  std::vector<Eigen::VectorXd> ends_s_;
  std::vector<double> ends_c_, ends_n_;
  int ends_ = 0;
  std::uint64_t held_kept_ = 0, held_refused_ = 0;
  long long residuals_seen_ = 0;
  int consecutive_ = 0, solves_ = 0;
  bool run_judged_ = false;  ///< a solve has refused samples of the current run of refusals
  std::uint64_t run_id_ = 0;  ///< which run of refusals is the current one (one more per run)
  std::vector<int> pending_place_;            ///< per held sample: its place in its run (0: none)
  std::vector<std::uint64_t> pending_run_;    ///< per held sample: its run
  std::uint64_t changes_ = 0, generation_ = 0;
};

}  // namespace inertial
