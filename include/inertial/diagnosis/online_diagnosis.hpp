/// @file online_diagnosis.hpp
/// What a running model lacks, judged on the stream itself while the online estimator runs
/// (inertiald, inertial replay): the diagnosis of joint_diagnosis.hpp without a held-out file.
///
/// Prequential judgement (Dawid, "Present position and potential developments: some personal views.
/// Statistical theory. The prequential approach", J. R. Stat. Soc. A 147(2), 1984): every sample is
/// first predicted, then learned from. The model's error on a sample is the online estimator's
/// residual r = tau - A w before it updates on that sample (OnlineJointEstimator::residual()); a
/// candidate effect's error is r less the candidate's torque with coefficients fitted on earlier
/// samples only. Both are held-out errors by construction, of the same samples, so the candidate
/// is judged exactly as joint_diagnosis.hpp judges one on a validation file: JudgeCandidate
/// (candidate_evidence.hpp) with the same evidence routes, prior odds, thresholds and ranking, on
/// the samples of the last `window_s` seconds.
///
/// Each candidate is fitted to the residual of its joint (the model's own coefficients stay as the
/// estimator has them): a recursive least-squares fit on that joint's features, forgotten
/// exponentially over fit_memory_s so that it follows the estimator as the links converge, and with
/// the coefficients the catalog requires to be non-negative (friction, armature, stiffness) held at
/// zero or above, as the batch fit's e^s parameters are.
/// Catalog (each where the model lacks it, on every DOF): viscous (qd), coulomb (tanh(qd / v_s)),
/// asymmetric ([s+, s-]; in place of a Coulomb step the model has), offset (1), armature (qdd),
/// spring ([q, 1]: k (q - q0)); payloads on links. Not online: the sigmoid form and the fitted
/// velocity scale of the dry-friction forms (both need a profile fit of the shape, friction_shape.hpp,
/// which `inertial diagnose` runs on a file); v_s is fixed (coulomb_velocity_scale).
///
/// Links are not refitted per candidate (that would take one estimator per candidate): what the
/// estimator's links absorb of a missing effect is not credited to it, so the judgement is
/// conservative. (A blocked refit of the links with each candidate over the last samples was tried:
/// it found the offsets the links absorb, but its ridge on the poorly excited link directions also
/// credited a constant column with what those directions leave, a false offset on a clean,
/// quantized CAN stream; see the README.)
/// A payload: a link whose
/// estimate departs from its URDF beyond the tolerance (plausibility.hpp, margins from the
/// estimator's covariance, departure_margins.hpp) by a physically consistent body added to it is
/// `payload@link`: held at its URDF with that payload, the link is believable again (it restores
/// the link's excess) and the data are explained as well. Route 3 (plausibility) applies to payloads
/// only: a joint effect's fit does not move the estimator's links.
///
/// Noise correlation: the autocorrelation time of each joint's noise (candidate_evidence.hpp) is
/// measured, as the batch diagnosis measures it, on the residual of the widest model: the links'
/// and the model's features and every candidate's, fitted by least squares (at Evaluate) to the
/// estimator's residual over the last autocorrelation_samples samples (fewer for large robots).
///
/// Cost: Add() is O(F^2) per DOF (F = 7 features, an 8 x 8 Gram matrix per joint), no allocation,
/// no exception; Evaluate() allocates and runs every few seconds, off the estimator's thread: the
/// widest model's least squares is held to about 2e8 multiply-adds.
/// Units: SI (N m, rad, s); time t in seconds, increasing.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "inertial/diagnosis/candidate_evidence.hpp"
#include "inertial/estimation/parameter_layout.hpp"
#include "inertial/inertia/plausibility.hpp"
#include "inertial/model/robot_dynamics.hpp"

namespace inertial {

struct OnlineDiagnosisOptions {
  /// Samples of the last window_s seconds are judged (a ring of `blocks` blocks of equal time).
  double window_s = 20.0;
  int blocks = 10;
  /// Memory of the candidates' coefficient fits [s] (exponential forgetting).
  double fit_memory_s = 10.0;
  /// The last samples kept (allocated once) for the noise's autocorrelation time (fewer are used
  /// for large robots, see Evaluate's cost).
  int autocorrelation_samples = 4096;
  /// v_s of the coulomb and asymmetric candidates [rad/s] (joint_effect.hpp's default).
  double coulomb_velocity_scale = 0.01;
  /// Joint effect kinds tested on every DOF (viscous, coulomb, asymmetric, offset, armature, spring).
  std::vector<EffectKind> joint_kinds{EffectKind::kViscous, EffectKind::kCoulomb,  EffectKind::kAsymmetric,
                                      EffectKind::kOffset,  EffectKind::kArmature, EffectKind::kSpring};
  EvidenceRules rules;
  /// Judged only once the window holds this many samples (too few say nothing).
  int min_samples = 200;
};

/// One estimated body as the online estimator has it now (for payload candidates).
struct OnlineBodyState {
  std::string name;
  bool link = false;             ///< a URDF link (not a rotor or a payload)
  InertialParams estimate, prior;  ///< in the body's report frame
  BodyUncertainty std;           ///< zeros when the estimator keeps no covariance
  Matrix10 pi_covariance = Matrix10::Zero();
};

/// The bodies of a running estimator: x its parameters (log-Cholesky relative to each prior, as
/// RobotDynamics), P their covariance (empty: none, e.g. the gradient law). With linear = true
/// (linear RLS) x is w: each tree body's pi directly and P its covariance.
std::vector<OnlineBodyState> OnlineBodyStates(const RobotDynamics& model, const Eigen::VectorXd& x,
                                              const Eigen::MatrixXd& P, bool linear);

struct OnlineCandidate {
  std::string name;      ///< e.g. "coulomb@knee", "payload@shank"
  EffectKind kind = EffectKind::kViscous;
  std::string joint;     ///< of a joint effect, else empty
  std::string link;      ///< of a payload, else empty
  std::string item;      ///< as --effects takes it, e.g. "coulomb@knee:scale=0.01"
  std::string replaces;  ///< the item it replaces (a joint's Coulomb step), else empty
  /// Fitted coefficients (RobotDynamics::EffectValues order: {b}, {bc}, {bp, bn}, {c}, {Ia},
  /// {k, q0}); a payload: its pi (10) in the link's report frame.
  std::vector<double> values;
  double rms_before = 0.0, rms_after = 0.0;  ///< its joint's prequential RMS without and with it [N m]
  CandidateEvidence evidence;
  std::string alternative_to;  ///< refitted together with this better one it adds nothing
};

struct OnlineDiagnosisResult {
  /// Every candidate judged: the suggestions first (num_suggestions of them), then the others,
  /// each part by score (candidate_evidence.hpp's ranking).
  std::vector<OnlineCandidate> candidates;
  int num_suggestions = 0;
  int samples = 0;                  ///< judged samples in the window
  double window_seconds = 0.0;      ///< time the judged samples span
  TorqueErrors model;               ///< the model's prequential errors over the window
  Eigen::VectorXd autocorrelation;  ///< per DOF, of the widest model's residual
  double implausibility = 0.0;      ///< B of the links (candidate_evidence.hpp)
  std::vector<std::string> bent_links;
  std::vector<std::string> notes;   ///< why nothing was judged, etc.
};

class OnlineDiagnosis {
 public:
  /// Candidates for `model` (the effects it has are not candidates). @throws std::invalid_argument
  /// for a non-positive window, memory, block or sample count.
  explicit OnlineDiagnosis(const RobotDynamics& model, const OnlineDiagnosisOptions& options = {});

  /// One sample the estimator accepted: its state (q, qd, qdd) and the estimator's residual before
  /// it updated on it (tau - predicted), per DOF. Samples of wrong size, non-finite or not after the
  /// last are ignored. Allocation-free, never throws.
  void Add(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd, const Eigen::VectorXd& qdd,
           const Eigen::VectorXd& tau, const Eigen::VectorXd& residual) noexcept;
  /// Forgets everything (the system changed: a payload picked up, a restart with another model).
  void Reset() noexcept;

  /// Judges every candidate on the window; `bodies` (OnlineBodyStates) for the payload candidates
  /// and the links' plausibility (empty: none).
  OnlineDiagnosisResult Evaluate(const std::vector<OnlineBodyState>& bodies = {}) const;

  int num_candidates() const { return static_cast<int>(candidates_.size()); }
  const RobotDynamics& model() const { return model_; }
  /// Samples in the window now.
  int samples() const;

  /// Per-DOF features, in the Gram matrix's order.
  enum Feature { kQd = 0, kTanh, kPositive, kNegative, kOne, kQdd, kQ, kNumFeatures };
  using Gram = Eigen::Matrix<double, kNumFeatures + 1, kNumFeatures + 1>;  ///< [features; residual]

 private:
  struct Candidate {
    EffectKind kind;
    int dof;
    int features[2];
    int num_features;
    bool non_negative;
    int parameters;
    PriorOdds odds;
    std::string name, item, replaces;
  };
  void Roll(double t);
  // The ring's last samples as one regression (the widest model, for the noise's correlation): rows
  // sample by sample (dofs each), columns the model's features (links and effects: `links` of
  // them) then every candidate's.
  struct RingRegression {
    int samples = 0, links = 0;
    std::vector<int> first_column;  // per candidate
    Eigen::MatrixXd X;
    Eigen::VectorXd y;              // the estimator's residual
  };
  RingRegression BuildRingRegression() const;
  Eigen::VectorXd WidestAutocorrelation(const RingRegression& g) const;
  // The steps of Evaluate: the time the judged samples span; a joint candidate's coefficients
  // from its joint's Gram matrix; every joint candidate judged on the window; the share of the
  // held-out error `k` removes beyond `top` (same joint) fitted together; the ranking
  // (candidate_ranking.hpp) with the near-ties and alternatives measured here.
  double WindowSeconds() const;
  std::vector<double> CandidateValues(const Candidate& k) const;
  void JudgeJointCandidates(const Eigen::VectorXd& sse0, const Eigen::VectorXd& tau_ss, OnlineDiagnosisResult* out) const;
  double AddedOverTop(const Candidate& top, const Candidate& k) const;
  void Rank(OnlineDiagnosisResult* out) const;

  RobotDynamics model_;
  OnlineDiagnosisOptions options_;
  std::vector<Candidate> candidates_;
  int dofs_ = 0;
  double block_s_ = 0.0;
  // Per DOF: the forgotten Gram matrix of the joint's features and residual.
  std::vector<Gram, Eigen::aligned_allocator<Gram>> gram_;
  // Blocks: [block][dof] squared residual of the model, squared torque; [block][candidate].
  Eigen::MatrixXd block_model_sse_, block_tau_ss_, block_candidate_sse_;
  Eigen::VectorXi block_count_;
  Eigen::VectorXd block_first_t_, block_last_t_;
  long long current_block_ = -1;  // absolute index of the block being filled
  // Ring of the last samples: [sample][residual, q, qd, qdd per DOF].
  Eigen::MatrixXd ring_;
  int ring_next_ = 0, ring_size_ = 0;
  long long samples_seen_ = 0;
  bool has_time_ = false;
  double last_t_ = 0.0, first_t_ = 0.0;
  Eigen::VectorXd phi_;  // scratch
};

}  // namespace inertial
