/// @file validation_report.hpp
/// `inertial validate` as a library: a given model (no fit) against measurements, its errors per
/// channel and in total, where it fails (the residual signatures of residual_analysis.hpp, as
/// `diagnose` shows them), and its text, JSON and --report outputs.
///
/// Robots: the model is a URDF with its effects (model_file.hpp), x from its stated values;
/// residual = predicted - measured torque per joint. Single bodies: a body pi and sensor effects
/// with values (body_effect_model.hpp); one "sample" per pair of log samples (the paper's
/// midpoint rule, eq. 13), channels mx my mz fx fy fz; the signatures use the matching twist
/// component as the "velocity" (a step at its reversal, a slope on it) and no position.
///
/// JSON: {model, data, samples, rms {channel..., total}, relative_rms {channel..., total},
/// where_it_fails {worst_windows, joints}, bodies | body, effects, physically_consistent}.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "inertial/estimation/batch/joint_identification.hpp"
#include "inertial/diagnosis/residual_analysis.hpp"
#include "inertial/model/body_effect_model.hpp"
#include "inertial/model/robot_dynamics.hpp"

namespace inertial {

/// A model's errors on a log. `signals` holds what the residual analysis saw: for robots the log
/// itself; for single bodies one row per pair (t at the midpoint, "qd" the matching twist component).
struct ModelValidation {
  std::string model_source, data_source;
  std::vector<std::string> channels;  ///< joint names, or mx .. fz
  std::string unit;                   ///< "N m", or "N m | N"
  TorqueErrors errors;
  Eigen::MatrixXd predicted;  ///< rows = samples (pairs), columns = channels
  JointSamples signals;
  ResidualAnalysis residuals;
  nlohmann::json model_json;  ///< the model's bodies / body and effects, as identify's JSON shows them
  bool physically_consistent = true;
  /// Samples left out of the errors because their measurement or the model's prediction is not
  /// finite (a glitch such as qd = 1e300 in the log), with the first few named.
  int left_out = 0;
  std::vector<std::string> left_out_reasons;
};

/// Magnitudes at or above this cannot enter an RMS: their squares, summed over a log, overflow.
inline constexpr double kLargestSquarable = 1e150;

/// The rows (ascending) where `predicted` or any of data's q, qd, qdd, tau is not finite, or a
/// torque or an error (predicted column c against data.tau column c mod joints) reaches
/// kLargestSquarable.
std::vector<int> NonFiniteRows(const Eigen::MatrixXd& predicted, const JointSamples& data);

/// The robot model at x on `data`; samples with a non-finite measurement or prediction are left
/// out of the errors and named. @throws std::invalid_argument if the data do not fit the model, or
/// no sample is left (naming why: e.g. a coefficient of the model so large that every prediction overflows).
ModelValidation ValidateJointModel(const RobotDynamics& model, const Eigen::VectorXd& x, const JointSamples& data);
/// The single-body model at x on `data` (at least 2 samples). @throws std::invalid_argument likewise.
ModelValidation ValidateBodyModel(const BodyEffectModel& model, const Eigen::VectorXd& x, const BodyLog& data);

std::string ValidationText(const ModelValidation& v);
nlohmann::json ValidationJson(const ModelValidation& v);
/// DIR/index.html with diagnose's figures (measured and predicted, residual against time and
/// against velocity, RMS per channel). @throws std::runtime_error from gnuplot or file writes.
void WriteValidationReport(const std::string& directory, const ModelValidation& v, const std::string& text);

}  // namespace inertial
