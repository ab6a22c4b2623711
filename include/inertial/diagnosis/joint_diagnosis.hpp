/// @file joint_diagnosis.hpp
/// Which physical effect a robot model lacks, judged on held-out data and on the plausibility of
/// the bodies each model leaves.
///
/// The model (links plus `effects`) is fitted to the training data as `identify` does (eq. 14,
/// joint_identification.hpp); then every candidate effect of the catalog that the model does not
/// have is added on its own, the model refitted, and judged (candidate_evidence.hpp) by the share
/// of the held-out mean-square error it removes, by the significance of that fall counted in
/// independent residual samples, and by how much more believable it leaves the links
/// (plausibility.hpp: each link against its URDF, outside the prior tolerance). Candidates are
/// ranked (candidate_evidence.hpp) by the held-out share they remove where the held-out data
/// support them, else by the plausibility they restore, near-ties to the simpler effect; those
/// some evidence supports are suggestions, best first. A suggestion that adds nothing to the
/// top one (refitted together, the pair is not supported over the top one alone) is marked as an
/// alternative to it and not suggested: both explain the same residual or the same bent link.
///
/// Catalog: viscous, coulomb, offset, armature and spring on each joint, and the asymmetric and
/// sigmoid friction forms where a joint's residual shows them (friction_shape.hpp fits the shape of
/// each dry-friction form first); payloads on links. One dry-friction form per joint: asymmetric or
/// sigmoid replaces a Coulomb step the model has on that joint (CandidateResult::replaces).
/// The candidate's judged parameters are its coefficients plus its fitted shape, less those of the
/// form it replaces.
///
/// Links and payloads: a payload rigidly fixed to a link is the same, to the data, as a change of
/// that link's inertia. With free links (the default), a link whose identified body departs from
/// its URDF by more than the prior tolerance is tested as `payload@link`: the link held at its URDF
/// and a payload body fitted on it (mass, COM and inertia). A payload in the model's own effects
/// holds its link the same way (link and payload would otherwise share the link's regressor
/// columns). With hold_links every link is held at its URDF and a payload is tested on every link.
///
/// Repeats: when the held-out data retrace the training trajectory (trajectory_overlap.hpp), a note
/// says that they cannot reveal overfitting.
///
/// Cost: the data enter once (and a subsample of at most 4000 training samples once more, for the
/// friction shapes), through A^T A of a model holding every candidate (training) and
/// per-joint A^T A (validation), plus one pass over the held-out samples for the noise's correlation
/// time; each candidate then costs one fit on those statistics, warm-started from the model's own
/// fit, and, where some link departs beyond the tolerance, one uncertainty decomposition (P x P);
/// each further suggestion one more fit together with the top one.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "inertial/diagnosis/candidate_evidence.hpp"
#include "inertial/diagnosis/departure_margins.hpp"
#include "inertial/diagnosis/model_comparison.hpp"
#include "inertial/estimation/parameter_layout.hpp"
#include "inertial/estimation/batch/joint_identification.hpp"
#include "inertial/inertia/plausibility.hpp"

namespace inertial {

// kDepartureMargin: departure_margins.hpp

/// Builds the robot's model with the given effects (throws std::invalid_argument on a bad effect).
using RobotModelFactory = std::function<RobotDynamics(const std::vector<EffectSpec>& effects)>;

struct JointDiagnosisOptions {
  JointIdentificationOptions fit;
  /// Hold the links at their priors (see the file comment) and test payload candidates on every link.
  bool hold_links = false;
  /// Optional: IterateJointDiagnosis calls it before each step with the step (1-based) and the cap.
  std::function<void(int step, int max_steps)> progress;
  /// With free links: test `payload@link` on every link outside the prior tolerance.
  bool payloads = true;
  /// A link is believable within a factor 1 + prior_tolerance of its URDF (plausibility.hpp).
  double prior_tolerance = kDefaultPriorTolerance;
  /// Share of the held-out mean-square error (averaged over joints) a candidate must remove to be
  /// suggested.
  double min_explained = 0.02;
  /// Smallest fall of some joint's held-out RMS, relative to its measured torque RMS.
  double min_gain = 0.005;
  /// Joint effect kinds tested on every joint (each only where the model lacks it).
  /// Coulomb, asymmetric and sigmoid friction get their shape fitted first (friction_shape.hpp);
  /// asymmetric and sigmoid are tested only on joints whose residual shows more than Coulomb's.
  std::vector<EffectKind> joint_kinds{EffectKind::kViscous,  EffectKind::kCoulomb, EffectKind::kAsymmetric,
                                      EffectKind::kSigmoid,  EffectKind::kOffset,  EffectKind::kArmature,
                                      EffectKind::kSpring};
  /// v_s of a Coulomb candidate where no fitted scale explains anything [rad/s]
  double coulomb_velocity_scale = 0.01;
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
  /// A richer dry-friction form replaces the joint's Coulomb step (one form per joint): the
  /// replaced term as an --effects item; empty when the candidate is added.
  std::string replaces;
  TorqueErrors validation;  ///< of the model with the candidate, on held-out data
  double explained = 0.0;   ///< see the file comment (may be negative: it made things worse)
  bool converged = false;
  int iterations = 0;
  std::vector<double> values;  ///< the fitted coefficients (RobotDynamics::EffectValues); payload: pi
  CandidateEvidence evidence;  ///< how it was judged (candidate_evidence.hpp)
  std::vector<BodyPlausibility> plausibility;  ///< of every estimated body of its fit
  double implausibility = 0.0;                 ///< B of its links
  std::string alternative_to;  ///< a suggestion that adds nothing to this better one (see the file comment)
  /// A payload: the standard deviations of its mass, COM and inertia (fit_uncertainty.hpp).
  std::optional<BodyUncertainty> payload_std;
};

struct JointDiagnosis {
  std::vector<EffectSpec> effects;      ///< of the model diagnosed
  std::vector<bool> frozen_bodies;      ///< bodies held at their priors
  JointIdentificationResult fit;        ///< the model's fit on the training data
  std::vector<std::string> body_names;  ///< of the model's estimated bodies
  std::vector<bool> links;              ///< which estimated bodies are URDF links (not rotors or payloads)
  std::vector<BodyPlausibility> plausibility;  ///< of every estimated body of the fit, against its prior
  double implausibility = 0.0;          ///< B of the fit's links (candidate_evidence.hpp)
  double prior_tolerance = kDefaultPriorTolerance;
  Eigen::VectorXd residual_tau;         ///< per joint: autocorrelation time of the noise (candidate_evidence.hpp)
  double retraced = 0.0;                ///< share of held-out samples retracing the training trajectory
  TorqueErrors fit_train, fit_validation, prior_validation;
  /// With effects: the held-out errors of the links alone (no effect), fitted the same way, so that
  /// the effects' gain shows (before -> after).
  std::optional<TorqueErrors> links_only_validation;
  /// The fitted model on the held-out data: its predictions and where it fails.
  ModelComparison held_out;
  /// Every candidate tested: the suggestions first, then the others, each part by score.
  std::vector<CandidateResult> candidates;
  int num_suggestions = 0;
  std::vector<std::string> notes;  ///< what was not tested and why, repeats
  std::string stop_reason;         ///< IterateJointDiagnosis: why the loop stopped
  int train_samples = 0, validation_samples = 0;
  double seconds = 0.0;            ///< wall time of the whole diagnosis
};

/// @param make the model factory; @param effects the model's effects; @param payload_links links
/// that may carry a payload (every one with options.hold_links; with free links those the fit bends).
/// @throws std::invalid_argument on bad effects or samples that do not match the model.
JointDiagnosis DiagnoseJointModel(const RobotModelFactory& make, const std::vector<EffectSpec>& effects,
                                  const std::vector<std::string>& payload_links, const JointSamples& train,
                                  const JointSamples& validation, const JointDiagnosisOptions& options = {});

/// The model's effects once `candidate` is taken: added, or in place of the dry-friction form it
/// replaces (effects stated for every joint are then written out per joint).
std::vector<EffectSpec> EffectsWithCandidate(const std::vector<EffectSpec>& effects,
                                             const std::vector<std::string>& joints, const CandidateResult& candidate);

/// One step of IterateJointDiagnosis: the effect added and the held-out errors before and after.
struct DiagnosisStep {
  std::string added;                ///< e.g. "coulomb@knee"
  std::string item;                 ///< as --effects takes it, e.g. "coulomb@knee:scale=0.0125"
  std::string replaced;             ///< the item it replaced (a joint's Coulomb step), or empty
  double explained = 0.0;           ///< the held-out share it removed when it was added
  CandidateEvidence evidence;       ///< how it was judged
  TorqueErrors before, after;       ///< held-out, of the model without and with it
  double implausibility_before = 0.0, implausibility_after = 0.0;  ///< B of the links
  std::vector<std::string> bent_before, bent_after;  ///< links outside the tolerance
};

/// The links (estimated bodies named after a URDF link) of a diagnosis's fit outside its tolerance.
std::vector<std::string> BentLinks(const JointDiagnosis& d);

/// Adds the top suggestion and diagnoses again, up to max_steps times or until nothing is
/// suggested (the loop a user runs by hand with --effects). *steps gets the path; the returned
/// diagnosis is that of the final model, whose effects are `effects` plus every added one.
JointDiagnosis IterateJointDiagnosis(const RobotModelFactory& make, const std::vector<EffectSpec>& effects,
                                     const std::vector<std::string>& payload_links, const JointSamples& train,
                                     const JointSamples& validation, const JointDiagnosisOptions& options,
                                     int max_steps, std::vector<DiagnosisStep>* steps);

/// The last `fraction` of a log's duration (HoldoutStart, sample_selection.hpp) as held-out data,
/// the rest for training. @throws std::invalid_argument as HoldoutStart.
void SplitHoldout(const JointSamples& data, double fraction, JointSamples* train, JointSamples* validation);

}  // namespace inertial
