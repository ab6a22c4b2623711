/// @file validation_report.hpp
/// `inertial validate` as a library: a given model (no fit) against measurements (the comparison
/// of model_comparison.hpp: errors per channel and in total, where it fails, as `diagnose` shows
/// them), and its text, JSON and --report outputs.
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

#include "inertial/diagnosis/model_comparison.hpp"

namespace inertial {

/// A model's errors on a log (model_comparison.hpp), with what the report names: the model and the
/// data, the model's bodies and effects as identify's JSON shows them, and their consistency.
struct ModelValidation : ModelComparison {
  std::string model_source, data_source;
  nlohmann::json model_json;  ///< the model's bodies / body and effects, as identify's JSON shows them
  bool physically_consistent = true;
  /// Several runs (validate with --data more than once): each run's own comparison, the pooled one
  /// being the fields above.
  std::vector<std::string> run_names;
  std::vector<ModelComparison> runs;
};

/// The robot model at x on `data` (CompareJointModel) and its bodies and effects.
/// @throws std::invalid_argument as CompareJointModel.
ModelValidation ValidateJointModel(const RobotDynamics& model, const Eigen::VectorXd& x, const JointSamples& data);
/// The single-body model at x on `data` (CompareBodyModel). @throws std::invalid_argument likewise.
ModelValidation ValidateBodyModel(const BodyEffectModel& model, const Eigen::VectorXd& x, const BodyLog& data);

std::string ValidationText(const ModelValidation& v);
nlohmann::json ValidationJson(const ModelValidation& v);
/// DIR/index.html with diagnose's figures (measured and predicted, residual against time and
/// against velocity, RMS per channel). @throws std::runtime_error from gnuplot or file writes.
void WriteValidationReport(const std::string& directory, const ModelValidation& v, const std::string& text);

}  // namespace inertial
