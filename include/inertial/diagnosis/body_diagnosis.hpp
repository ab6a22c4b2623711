/// @file body_diagnosis.hpp
/// Fitting a single rigid body with sensor effects (body_effect_model.hpp) by Levenberg-Marquardt
/// over x (theta and the effects' parameters: every iterate a consistent body), and finding which
/// effect the model lacks on held-out data, as joint_diagnosis.hpp does for robots: each candidate
/// of force_bias, moment_bias, velocity_bias and gravity the model lacks is added on its own, the
/// model refitted on the training log, and ranked by the share of the held-out mean-square wrench
/// error it removes, averaged over the six wrench components (explained_error.hpp), and by the
/// significance of that fall (candidate_evidence.hpp; a single body has no URDF to be plausible
/// against, so the plausibility route is not used).
///
/// Short logs. The paper's setting (Section VI) has 63 samples: a held-out third is 21 samples, on
/// which the noise of a single split decides (over 20 clean bodies a 0.3 split raised 3 false
/// alarms). DiagnoseBodyModelCrossValidated judges by blocked k-fold cross-validation instead:
/// the pairs are cut into k contiguous blocks; each block is predicted by a fit on the others
/// (less the pair on each side of the block, which shares a sample with it), so every pair is
/// held out once and the held-out error is measured on all of them. Blocks, not random pairs,
/// because neighbouring samples share noise (the twist of a sample enters two pairs) and a smooth
/// trajectory makes neighbours nearly equal: a random split would let the fit see each held-out
/// pair's twin.
#pragma once

#include <string>
#include <vector>

#include "inertial/diagnosis/candidate_evidence.hpp"
#include "inertial/estimation/batch/dense_levenberg_marquardt.hpp"
#include "inertial/estimation/batch/joint_identification.hpp"
#include "inertial/model/body_effect_model.hpp"

namespace inertial {

struct BodyFit {
  Eigen::VectorXd x;
  DenseLevenbergMarquardtResult lm;
};

/// Minimizes 0.5 sum_pairs ||predicted - measured||^2 from `initial` (empty: the prior, zero
/// effects). @throws std::invalid_argument if the log has fewer than 2 samples or sizes disagree.
/// `pairs`: the pairs fitted (empty: all).
BodyFit FitBodyModel(const BodyEffectModel& model, const BodyLog& log, const LevenbergMarquardtOptions& options,
                     const Eigen::VectorXd& initial = Eigen::VectorXd(), const std::vector<int>& pairs = {});

/// RMS of the residuals per wrench component [mx my mz fx fy fz], their totals pooled (relative:
/// to the RMS of the measured wrench).
TorqueErrors WrenchErrors(const BodyEffectModel& model, const Eigen::VectorXd& x, const BodyLog& log);

struct BodyDiagnosisOptions {
  /// Generous caps: a velocity bias makes the problem strongly nonlinear.
  LevenbergMarquardtOptions fit{500, 1e-10, 1e-10, 1e-10, 1e-3, true, {}};
  double min_explained = 0.02;  ///< as JointDiagnosisOptions::min_explained
  double min_gain = 0.005;      ///< as JointDiagnosisOptions::min_gain (per wrench component)
  int folds = 5;                ///< blocks of DiagnoseBodyModelCrossValidated
};

/// Fewest pairs per block of the cross-validation (a block of fewer cannot be told from its noise).
inline constexpr int kMinPairsPerFold = 4;

struct BodyCandidateResult {
  BodyEffectKind kind = BodyEffectKind::kForceBias;
  TorqueErrors validation;
  double explained = 0.0;
  bool converged = false;
  int iterations = 0;
  Eigen::VectorXd values;  ///< the fitted effect parameters
  CandidateEvidence evidence;
};

struct BodyDiagnosis {
  std::vector<BodyEffectKind> effects;
  BodyFit fit;
  TorqueErrors fit_train, fit_validation, prior_validation;
  std::vector<BodyCandidateResult> candidates;  ///< best first
  int num_suggestions = 0;
  int train_pairs = 0, validation_pairs = 0;
  int folds = 0;                  ///< cross-validation blocks (0: a held-out log)
  Eigen::VectorXd residual_tau;   ///< per wrench component, of the model's held-out residual (JSON)
  double seconds = 0.0;
};

BodyDiagnosis DiagnoseBodyModel(const InertialParams& prior, const std::vector<BodyEffectKind>& effects,
                                const BodyLog& train, const BodyLog& validation,
                                const BodyDiagnosisOptions& options = {});

/// The same judged by blocked options.folds-fold cross-validation of one log (see the file
/// comment): validation errors are those of the cross-validated predictions of every pair;
/// fit and fit_train are the fit on the whole log.
/// @throws std::invalid_argument if folds < 2 or the log has fewer than folds * kMinPairsPerFold
/// pairs (naming both), or as DiagnoseBodyModel.
BodyDiagnosis DiagnoseBodyModelCrossValidated(const InertialParams& prior, const std::vector<BodyEffectKind>& effects,
                                              const BodyLog& log, const BodyDiagnosisOptions& options = {});

/// The last `fraction` of the samples as held-out data. @throws std::invalid_argument unless
/// 0 < fraction < 1 and both parts keep at least 3 samples.
void SplitHoldout(const BodyLog& log, double fraction, BodyLog* train, BodyLog* validation);

}  // namespace inertial
