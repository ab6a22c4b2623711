/// @file diagnosis_report.hpp
/// Output of `inertial diagnose`: the text report, the JSON document, the one-line physical
/// explanation of each candidate effect, and the --report page (diagnosis_html.hpp), for robots
/// (joint_diagnosis.hpp) and single bodies (body_diagnosis.hpp).
///
/// JSON (robots): rms_validation {joint..., total}, relative_rms_validation, rms_prior (the URDF
/// without effects, held-out), rms_links_only (with --effects: the links alone), rms_train, effects
/// (the model's, with fitted values), suggestions [{effect, joint | link, rms_validation_after
/// {joint..., total}, explained, explanation, values}], candidates (every one tested, same fields,
/// with suggested, score, evidence {explained, significance, threshold, restored, by_size,
/// by_significance, by_plausibility}, alternative_to), physically_consistent, bodies (identified
/// parameters, as identify's JSON), plausibility (PlausibilityJson), prior_tolerance,
/// implausibility, bent_links, validation_retraces_training (share of held-out samples),
/// where_it_fails {worst_windows [{t_start, t_end, rms, worst_joint}], joints {j: {mean,
/// velocity_sign_step, viscous_slope, acceleration_slope, position_slope, torque_slope,
/// correlations{...}, explained}}}, min_explained, notes, seconds, samples.
/// Single bodies: the same keys, channels mx..fz instead of joints, suggestions with "target":
/// "body", and "body" (mass, com, inertia, pi, theta, physically_consistent) instead of bodies.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "inertial/diagnosis/body_diagnosis.hpp"
#include "inertial/diagnosis/joint_diagnosis.hpp"
#include "inertial/diagnosis/residual_analysis.hpp"

namespace inertial {

/// Everything the robot report needs: the model diagnosed and its diagnosis (with the fit's
/// held-out comparison, JointDiagnosis::held_out, where it fails).
struct JointDiagnosisContext {
  const RobotDynamics* model = nullptr;  ///< the model diagnosed (its effects)
  const JointDiagnosis* diagnosis = nullptr;
  std::string validation_source;  ///< e.g. "test.csv" or "the last 30 % of train.csv"
  double min_explained = 0.02;
  double min_gain = 0.005;         ///< JointDiagnosisOptions::min_gain
  /// Several runs: the fitted model's held-out comparison run by run (the pooled one is the
  /// diagnosis's held_out).
  std::vector<std::string> run_names;
  std::vector<ModelComparison> runs;
};

/// Every identified body against its URDF (plausibility.hpp): mass ratio, COM shift, principal
/// moment ratios, divergence, factor; and a line for each link that bends beyond the tolerance.
std::string PlausibilityText(const RobotDynamics& model, const JointDiagnosis& d);
/// [{name, mass, mass_prior, mass_ratio, com_shift_mm, com_shift_relative, principal_moment_ratios,
/// inertia_change, divergence, factor, raw_factor, link, within_tolerance}] (infinities as "inf").
nlohmann::json PlausibilityJson(const RobotDynamics& model, const JointDiagnosis& d);

/// "Where it fails (<what>)": the worst windows and each joint's residual signature, as text.
std::string WhereItFailsText(const std::vector<std::string>& dof_names, const ResidualAnalysis& residuals,
                             const std::string& what);
/// {worst_windows [{t_start, t_end, rms, worst_joint}], joints {j: {rms, mean, velocity_sign_step,
/// viscous_slope, acceleration_slope, position_slope, torque_slope, correlations, explained}}}.
nlohmann::json WhereItFailsJson(const std::vector<std::string>& dof_names, const ResidualAnalysis& residuals);

JointDiagnosisContext MakeJointDiagnosisContext(const RobotDynamics& model, const JointDiagnosis& diagnosis,
                                                const std::string& validation_source, double min_explained);

/// One line: what the residual shows and what is missing, with the fitted coefficient.
std::string CandidateExplanation(const JointDiagnosisContext& c, const CandidateResult& candidate);

std::string JointDiagnosisText(const JointDiagnosisContext& c);
nlohmann::json JointDiagnosisJson(const JointDiagnosisContext& c);
/// @throws std::runtime_error from gnuplot or file writes.
void WriteJointDiagnosisReport(const std::string& directory, const JointDiagnosisContext& c, const std::string& text);

/// The path of IterateJointDiagnosis: one line per added effect, held-out RMS before -> after;
/// and as JSON [{added, explained, rms_validation_before, rms_validation_after}].
std::string DiagnosisPathText(const std::vector<DiagnosisStep>& path, const JointDiagnosis& final_diagnosis);
nlohmann::json DiagnosisPathJson(const RobotDynamics& model, const std::vector<DiagnosisStep>& path);

struct BodyDiagnosisContext {
  const BodyDiagnosis* diagnosis = nullptr;
  const BodyLog* validation = nullptr;
  InertialParams prior;
  std::string validation_source;
  double min_explained = 0.02;
  double min_gain = 0.005;  ///< BodyDiagnosisOptions::min_gain
  /// Glitched samples left out before the fit (sample_glitches.hpp), one sentence each, prefixed
  /// with their file: JSON "left_out".
  std::vector<std::string> left_out;
};

std::string BodyCandidateExplanation(const BodyCandidateResult& candidate);
std::string BodyDiagnosisText(const BodyDiagnosisContext& c);
nlohmann::json BodyDiagnosisJson(const BodyDiagnosisContext& c);
void WriteBodyDiagnosisReport(const std::string& directory, const BodyDiagnosisContext& c, const std::string& text);

}  // namespace inertial
