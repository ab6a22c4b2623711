/// @file identification_report.hpp
/// `inertial identify` as a library: the robot model from a URDF plus effects, the run (train and
/// optional validation data, the fit, the prior's and the fit's torque errors, the unidentified
/// directions), and its text and JSON reports.
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "inertial/estimation/fit_uncertainty.hpp"
#include "inertial/estimation/batch/identifiability.hpp"
#include "inertial/estimation/batch/joint_identification.hpp"
#include "inertial/estimation/batch/robust_identification.hpp"
#include "inertial/formats/model_file.hpp"
#include "inertial/formats/urdf_model.hpp"

namespace inertial {

struct IdentificationRun {
  JointIdentificationResult fit;
  double fit_seconds = 0.0;            ///< regressor, A^T A and LM, every round of the outlier screening
  int train_samples = 0, validation_samples = 0;
  int validation_left_out = 0;  ///< validation rows with a non-finite value or prediction, not in its errors
  double prior_weight = 0.0;           ///< gamma of eq. 14 used
  /// prior_*: the URDF's bodies without any effect; fit_*: the identified model.
  TorqueErrors prior_train, fit_train;
  std::optional<TorqueErrors> prior_validation, fit_validation;
  IdentifiabilityReport identifiability;
  /// Training rows left out as outliers (robust_identification.hpp); the training errors are of the kept rows.
  OutlierReport outliers;
  /// Standard deviations (fit_uncertainty.hpp); nullopt with the reason when they cannot be had
  /// (no residual degrees of freedom).
  std::optional<FitUncertainty> uncertainty;
  std::string uncertainty_unavailable;
  /// The fit ended on a numerical failure or with non-finite numbers.
  bool failed() const;
};

/// Fits `model` to `train` with outlier rejection (and evaluates on `validation` when given: every
/// row, nothing rejected there), then the fit's uncertainty.
/// @throws std::invalid_argument if no training row is left (the message names why).
IdentificationRun RunIdentification(const RobotDynamics& model, const JointSamples& train,
                                    const JointSamples* validation, const JointIdentificationOptions& options,
                                    const OutlierOptions& outliers = {});

/// The human-readable report (links with mass, COM, inertia about the COM, principal moments and
/// axes, consistency; effects; per-joint errors; unidentified directions, at most `max_directions`;
/// the identifiable combinations with their values and stds, at most 30, the least certain).
std::string IdentificationText(const RobotDynamics& model, const IdentificationRun& run, int max_directions = 12);

/// JSON: {iterations, stop_reason, outliers{rejected, rows (first 20 sample indices), threshold,
/// scale{joint...}, reasons}, noise_sigma, bodies[..., uncertainty{mass_std, com_std,
/// inertia_about_com_std, held_by_prior}], effects[..., std{...}], converged, fit_seconds, prior_weight, cost{data, regularizer},
/// rms_train{per joint, total}, relative_rms_train, rms_prior_train, (and _validation), bodies[{name,
/// mass, com, inertia_about_com (3x3), principal_moments, principal_axes (columns), pi, theta,
/// consistency{...}, physically_consistent}], effects[{effect, joint, values{...}}],
/// physically_consistent (all bodies), unidentified{rank, parameters, directions[{description, terms}]},
/// base_combinations[{terms [[name, coefficient], ...], text, value, std (null without the fit's
/// uncertainty, "inf" if undetermined), held_by_prior}] (identifiability.hpp, fit_uncertainty.hpp)}.
nlohmann::json IdentificationJson(const RobotDynamics& model, const IdentificationRun& run);

/// The "bodies" array of IdentificationJson at x; *all_consistent (optional) tells whether every
/// body passed the consistency check.
nlohmann::json BodiesJson(const RobotDynamics& model, const Eigen::VectorXd& x, bool* all_consistent = nullptr);
/// The "effects" array of IdentificationJson at x.
nlohmann::json EffectsJson(const RobotDynamics& model, const Eigen::VectorXd& x);
/// {"<joint>": value, ..., "total": total}.
nlohmann::json PerJointJson(const RobotDynamics& model, const Eigen::VectorXd& per_joint, double total);
/// The units of effect values (EffectValueNames, joint_effect.hpp: "b" in "N m s/rad", ...) for
/// revolute joints.
std::vector<std::string> EffectValueUnits(EffectKind kind);

}  // namespace inertial
