/// @file joint_diagnosis.hpp
/// Which physical effect a robot model lacks, judged on held-out data.
///
/// The model (links plus `effects`) is fitted to the training data as `identify` does (eq. 14,
/// joint_identification.hpp); then every candidate effect of the catalog that the model does not
/// have (viscous, coulomb, offset, armature and spring on each joint; with hold_links, a payload
/// on each link) is added on its own, the model refitted, and its torque error measured on the
/// validation data, which no fit sees. A candidate's score is the share of the held-out mean-square
/// error it removes, averaged over joints (explained_error.hpp), so overfitting is not rewarded
/// (a coefficient fitted to noise does not lower the error on other data) and every joint counts
/// alike whatever its torque scale. Candidates are ranked by it (near-ties to the simpler effect);
/// those the held-out data support (explained_error.hpp: explaining at least min_explained,
/// lowering the pooled error, and lowering some joint's error by min_gain of its torque) are
/// suggestions. A model that lacks nothing gets none; nor does a model whose own fit did not
/// converge (its candidates would all look good: a note says so).
///
/// Links and payloads: a payload rigidly fixed to a link is the same, to the data, as a change of
/// that link's inertia, which a fit with free links identifies already. Payload candidates are
/// therefore tested only with hold_links (the links' URDF inertias trusted and held at their
/// priors, rotors and payloads still fitted), where a payload is the question "which link carries
/// more than its URDF says".
///
/// Cost: the data enter once, through A^T A of a model holding every candidate (training) and
/// per-joint A^T A (validation); each candidate then costs one fit on those statistics, warm-started
/// from the model's own fit.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "inertial/estimation/joint_identification.hpp"

namespace inertial {

/// Builds the robot's model with the given effects (throws std::invalid_argument on a bad effect).
using RobotModelFactory = std::function<RobotDynamics(const std::vector<EffectSpec>& effects)>;

struct JointDiagnosisOptions {
  JointIdentificationOptions fit;
  /// Hold the links at their priors (see the file comment) and test payload candidates.
  bool hold_links = false;
  /// Share of the held-out mean-square error (averaged over joints) a candidate must remove to be
  /// suggested.
  double min_explained = 0.02;
  /// Smallest fall of some joint's held-out RMS, relative to its measured torque RMS.
  double min_gain = 0.005;
  /// Joint effect kinds tested on every joint (each only where the model lacks it).
  std::vector<EffectKind> joint_kinds{EffectKind::kViscous, EffectKind::kCoulomb, EffectKind::kOffset,
                                      EffectKind::kArmature, EffectKind::kSpring};
  double coulomb_velocity_scale = 0.01;  ///< v_s of the Coulomb candidates [rad/s]
  /// Worker threads for the candidate fits (0: one per hardware thread).
  int threads = 0;
};

/// Torque errors from per-joint statistics (normal equations) and coefficients w.
TorqueErrors ErrorsFromNormalEquations(const std::vector<JointNormalEquations>& jointwise, const Eigen::VectorXd& w);

struct CandidateResult {
  EffectSpec spec;
  std::string name;        ///< e.g. "coulomb@knee", "payload@tool0"
  std::string joint;       ///< the joint of a joint effect, else empty
  std::string link;        ///< the link of a payload, else empty
  TorqueErrors validation;  ///< of the model with the candidate, on held-out data
  double explained = 0.0;   ///< see the file comment (may be negative: it made things worse)
  bool converged = false;
  int iterations = 0;
  std::vector<double> values;  ///< the fitted coefficients (RobotDynamics::EffectValues); payload: pi
};

struct JointDiagnosis {
  std::vector<EffectSpec> effects;      ///< of the model diagnosed
  std::vector<bool> frozen_bodies;      ///< bodies held at their priors
  JointIdentificationResult fit;        ///< the model's fit on the training data
  TorqueErrors fit_train, fit_validation, prior_validation;
  /// With effects: the held-out errors of the links alone (no effect), fitted the same way, so that
  /// the effects' gain shows (before -> after).
  std::optional<TorqueErrors> links_only_validation;
  /// Every candidate tested, best first; the first num_suggestions of them are the suggestions.
  std::vector<CandidateResult> candidates;
  int num_suggestions = 0;
  std::vector<std::string> notes;  ///< what was not tested and why
  int train_samples = 0, validation_samples = 0;
  double seconds = 0.0;            ///< wall time of the whole diagnosis
};

/// @param make the model factory; @param effects the model's effects; @param payload_links links
/// that may carry a payload (tested with options.hold_links only).
/// @throws std::invalid_argument on bad effects or samples that do not match the model.
JointDiagnosis DiagnoseJointModel(const RobotModelFactory& make, const std::vector<EffectSpec>& effects,
                                  const std::vector<std::string>& payload_links, const JointSamples& train,
                                  const JointSamples& validation, const JointDiagnosisOptions& options = {});

/// One step of IterateJointDiagnosis: the effect added and the held-out errors before and after.
struct DiagnosisStep {
  std::string added;                ///< e.g. "coulomb@knee"
  double explained = 0.0;           ///< its score when it was added
  TorqueErrors before, after;       ///< held-out, of the model without and with it
};

/// Adds the top suggestion and diagnoses again, up to max_steps times or until nothing is
/// suggested (the loop a user runs by hand with --effects). *steps gets the path; the returned
/// diagnosis is that of the final model, whose effects are `effects` plus every added one.
JointDiagnosis IterateJointDiagnosis(const RobotModelFactory& make, const std::vector<EffectSpec>& effects,
                                     const std::vector<std::string>& payload_links, const JointSamples& train,
                                     const JointSamples& validation, const JointDiagnosisOptions& options,
                                     int max_steps, std::vector<DiagnosisStep>* steps);

/// The last `fraction` of a log (by sample count) as held-out data, the rest for training.
/// @throws std::invalid_argument unless 0 < fraction < 1 and both parts keep at least 2 samples.
void SplitHoldout(const JointSamples& data, double fraction, JointSamples* train, JointSamples* validation);

}  // namespace inertial
