/// @file robust_identification.hpp
/// Batch identification (joint_identification.hpp) that survives glitched samples: rows whose
/// torque residual is far outside the robust spread of all residuals are left out of the fit.
///
/// Why: the fit minimizes squared torque errors through A^T A, A^T tau and tau^T tau, so one row
/// with tau = 1e6 N m among ten thousand moves the fit by orders of magnitude, and a row with
/// tau or qd = 1e300 makes the sums overflow. Real logs have such rows: bus errors, a sensor that
/// reports its saturation value, a counter read as a float.
///
/// Method (IdentifyJointModelRobust), per sample i and joint j, residual r_ij = (A_i w(x) - tau_i)_j:
///   1. Rows with a non-finite q, qd, qdd or tau, a non-finite regressor A_i (e.g. qd = 1e300:
///      qd^2 overflows) or a non-finite prior prediction are rejected outright, for good.
///   2. The residuals of the prior model (x = PriorParametersWithoutEffects: the URDF's bodies,
///      no effects) give, per joint, the median m_j and the robust scale s_j = 1.4826 MAD_j (the
///      standard deviation for Gaussian residuals; 50 % breakdown point, so a glitch cannot inflate
///      it). A row is rejected if |r_ij - m_j| > k s_j for any joint j.
///   3. The model is fitted (IdentifyJointModel with the caller's options) on the kept rows; the
///      residuals of ALL rows of step 2 under that fit give new m_j, s_j and a new rejected set
///      (rows may come back: the prior's errors are larger than the fit's, and structured, so
///      step 2 may reject good rows at the extremes of the excitation). Repeated until the set is
///      unchanged or after max_rounds fits. The prior is only a starting point: what is rejected
///      in the end is judged against the fit of the kept data.
///
/// The threshold k (OutlierOptions::threshold = 0): DefaultOutlierThreshold (signal/robust_statistics.hpp,
/// which says why).
///
/// The scale floor: s_j >= 1e-3 RMS_j(tau) and s_j >= 1e-9 (N m or N), where RMS_j(tau) is the RMS
/// of joint j's measured torque over the rows of step 2 within k robust scales of that column's own
/// median (so a glitch does not inflate it). 1e-3 of the torque's RMS is below the resolution of
/// real joint-torque sensing (motor-current torque estimates are good to about 1 %, strain-gauge
/// sensors to 0.1-1 % of their range): a residual spread below it is rounding or model-class
/// detail, not noise, and noise-free simulated data would otherwise reject rows over rounding-level
/// residuals whose MAD is ~1e-12. 1e-9 N m is far below any sensor, for a joint whose torque is
/// identically zero.
///
/// Cost: each round accumulates the normal equations of the kept rows and evaluates the regressor
/// of every row once, O(rows x features^2); the fit itself is O(features^3) per LM iteration.
/// Conventions: SI units; rows are samples, columns joints in the model's DOF order (joint_samples.hpp).
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "inertial/estimation/batch/joint_identification.hpp"
#include "inertial/model/joint_samples.hpp"
#include "inertial/model/robot_dynamics.hpp"
#include "inertial/signal/robust_statistics.hpp"
#include "inertial/signal/sample_selection.hpp"

namespace inertial {

struct OutlierOptions {
  bool enabled = true;      ///< false: IdentifyJointModel on all rows, exactly
  double threshold = 0.0;   ///< k in robust standard deviations; 0: from the number of residuals (above)
  int max_rounds = 5;       ///< fits at most (each followed by a new rejected set), >= 1
  /// Several runs laid end to end (RecordedRuns::starts: each run's first row, then the number of
  /// rows): the center m_j and scale s_j of steps 2 and 3, and the scale floor, are found run by
  /// run, so that a quiet run is not judged by a noisy one's spread nor a noisy one by a quiet
  /// one's (two runs of which one is noise-free would otherwise lose the other whole). Empty: one run.
  std::vector<int> run_starts;
};

struct OutlierReport {
  std::vector<int> rejected;        ///< sample indices left out of the fit, ascending
  std::vector<int> non_finite;      ///< those of them rejected in step 1 (non-finite values), ascending
  Eigen::VectorXd scale;            ///< per joint robust residual scale s_j (floored) that decided `rejected` [N m or N] (the first run's)
  Eigen::VectorXd center;           ///< per joint median residual m_j of the same classification [N m or N] (the first run's)
  Eigen::MatrixXd run_scale, run_center;  ///< the same per run (rows) and joint (columns)
  std::vector<int> rejected_by_run, rows_by_run;  ///< rows left out and rows, per run
  double threshold = 0.0;           ///< the k used
  int rounds = 0;                   ///< fits done
  bool settled = false;             ///< the last fit's residuals gave the same rejected set (false: max_rounds hit)
  /// For the first few rejected rows (ascending), one sentence each: the sample, its time, and the
  /// joint with its residual against k s_j, or "non-finite qd_hip" etc.
  std::vector<std::string> reasons;
};

struct RobustIdentificationResult {
  JointIdentificationResult fit;    ///< IdentifyJointModel on the kept rows (bit for bit)
  OutlierReport outliers;
  JointNormalEquations equations;   ///< of the kept rows
};

/// Identification with outlier rejection (the method above). With outliers.enabled = false, the
/// result is IdentifyJointModel(model, AccumulateNormalEquations(model, data), options) on all rows.
/// @throws std::invalid_argument as IdentifyJointModel and AccumulateNormalEquations, for
///   max_rounds < 1 or a negative or non-finite threshold, and (enabled) if no row is left
///   (the message names the first rows' reasons).
RobustIdentificationResult IdentifyJointModelRobust(const RobotDynamics& model, const JointSamples& data,
                                                    const JointIdentificationOptions& options,
                                                    const OutlierOptions& outliers = {});

/// What in the data could make a fit fail, for its error message: up to max_items sentences such as
/// "sample 5000 (t = 10 s): tau_knee = 1e+06, 2.4e+05 robust scales from the column's median 0.31",
/// naming non-finite values first (in sample order), then values more than 1e6 robust scales
/// (1.4826 MAD) from their column's median, most extreme first; columns q_J, qd_J, qdd_J, tau_J.
/// Why 1e6: the extremes of a real signal are a few robust scales out (a sinusoid's peak is 1.4, a
/// Gaussian's one-in-a-billion value 6, a torque spike of a collision tens); a million can only be
/// a glitch, a unit or encoding error (a raw counter, an epoch time, a saturation code); and such
/// values are what overflow the normal equations (their squares times the regressor's). The scale
/// is floored at 1e-6 of the column's median absolute value (and at 1e-300), so that a column that
/// is constant but for a glitch still names the glitch but not a value that merely differs by 1e-6.
/// Empty when nothing stands out.
std::vector<std::string> DescribeExtremeValues(const JointSamples& data, int max_items = 3);

}  // namespace inertial
