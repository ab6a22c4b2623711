/// @file model_comparison.hpp
/// A model against measurements, with no fit: its predictions, its errors per channel and in
/// total, and where it fails (the residual signatures of residual_analysis.hpp over 1 s windows,
/// the 3 worst named). `validate` shows this for a stated model, `diagnose` for its fitted model on
/// the held-out data (JointDiagnosis::held_out); the report layer only formats it.
///
/// Robots: residual = predicted - measured torque per joint. Single bodies: one "sample" per pair
/// of log samples (the paper's midpoint rule, eq. 13), channels mx my mz fx fy fz; the signatures
/// use the matching twist component as the "velocity" (a step at its reversal, a slope on it) and
/// no position.
#pragma once

#include <string>
#include <vector>

#include "inertial/diagnosis/residual_analysis.hpp"
#include "inertial/estimation/batch/joint_identification.hpp"
#include "inertial/model/body_effect_model.hpp"
#include "inertial/model/robot_dynamics.hpp"
#include "inertial/signal/recorded_runs.hpp"

namespace inertial {

/// "Where it fails" looks at windows of this length and names the worst few: a second holds
/// several periods of the excitations identification uses (0.1-1 Hz) at any logging rate, short
/// enough to point at one motion.
inline constexpr double kFailureWindowSeconds = 1.0;
inline constexpr int kWorstFailureWindows = 3;

/// Magnitudes at or above this cannot enter an RMS: their squares, summed over a log, overflow.
inline constexpr double kLargestSquarable = 1e150;

/// A model's errors on a log. `signals` holds what the residual analysis saw: for robots the log
/// itself (without the rows left out); for single bodies one row per pair (t at the midpoint, "qd"
/// the matching twist component).
struct ModelComparison {
  std::vector<std::string> channels;  ///< joint names, or mx .. fz
  std::string unit;                   ///< "N m", or "N m | N"
  TorqueErrors errors;
  Eigen::MatrixXd predicted;  ///< rows = samples (pairs), columns = channels
  JointSamples signals;
  ResidualAnalysis residuals;
  /// Samples left out of the errors because their measurement or the model's prediction is not
  /// finite (a glitch such as qd = 1e300 in the log), with the first few named.
  int left_out = 0;
  std::vector<std::string> left_out_reasons;
};

/// The rows (ascending) where `predicted` or any of data's q, qd, qdd, tau is not finite, or a
/// torque or an error (predicted column c against data.tau column c mod joints) reaches
/// kLargestSquarable.
std::vector<int> NonFiniteRows(const Eigen::MatrixXd& predicted, const JointSamples& data);

/// The robot model at x on `data`; samples with a non-finite measurement or prediction are left
/// out and named. @throws std::invalid_argument if the data do not fit the model, or no sample is
/// left (naming why: e.g. a coefficient of the model so large that every prediction overflows).
ModelComparison CompareJointModel(const RobotDynamics& model, const Eigen::VectorXd& x, const JointSamples& data);
/// The same, run by run (runs.Run(k): each run's own errors and signatures).
/// @throws std::invalid_argument as CompareJointModel, naming the run.
std::vector<ModelComparison> CompareJointModelByRun(const RobotDynamics& model, const Eigen::VectorXd& x,
                                                    const RecordedRuns& runs);
/// The single-body model at x on `data` (at least 2 samples). @throws std::invalid_argument likewise.
ModelComparison CompareBodyModel(const BodyEffectModel& model, const Eigen::VectorXd& x, const BodyLog& data);

}  // namespace inertial
