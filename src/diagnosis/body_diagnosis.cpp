#include "inertial/diagnosis/body_diagnosis.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include "inertial/diagnosis/candidate_ranking.hpp"
#include "inertial/diagnosis/explained_error.hpp"

namespace inertial {
namespace {

void CheckLog(const BodyLog& log) {
  if (log.samples.size() < 2) throw std::invalid_argument("single-body fit: fewer than 2 samples");
  if (!log.gravity.empty() && log.gravity.size() != log.samples.size()) {
    throw std::invalid_argument("single-body fit: gravity must be empty or one vector per sample");
  }
}

}  // namespace

BodyFit FitBodyModel(const BodyEffectModel& model, const BodyLog& log, const LevenbergMarquardtOptions& options,
                     const Eigen::VectorXd& initial, const std::vector<int>& pairs) {
  CheckLog(log);
  for (int i : pairs) {
    if (i < 0 || i >= log.num_pairs()) throw std::invalid_argument("single-body fit: a pair index outside the log");
  }
  const int P = model.num_parameters();
  Eigen::VectorXd x0 = initial.size() == 0 ? Eigen::VectorXd::Zero(P) : initial;
  if (x0.size() != P) throw std::invalid_argument("single-body fit: the start has the wrong size");
  Eigen::MatrixXd J(6, P);
  const NormalEquationsFn problem = [&](const Eigen::VectorXd& x, double* F, Eigen::VectorXd* g, Eigen::MatrixXd* H) {
    const bool derivatives = g != nullptr && H != nullptr;
    double cost = 0.0;
    if (derivatives) {
      g->setZero(P);
      H->setZero(P, P);
    }
    const int count = pairs.empty() ? log.num_pairs() : static_cast<int>(pairs.size());
    for (int k = 0; k < count; ++k) {
      const int i = pairs.empty() ? k : pairs[k];
      const Vector6 r = model.PredictPair(x, log, i, derivatives ? &J : nullptr) - BodyEffectModel::MeasuredPair(log, i);
      cost += r.squaredNorm();
      if (derivatives) {
        g->noalias() += J.transpose() * r;
        H->selfadjointView<Eigen::Lower>().rankUpdate(J.transpose());
      }
    }
    if (derivatives) H->triangularView<Eigen::StrictlyUpper>() = H->transpose();
    *F = 0.5 * cost;
    return std::isfinite(*F);
  };
  BodyFit fit;
  fit.lm = MinimizeLevenbergMarquardt(problem, x0, options);
  fit.x = fit.lm.x;
  return fit;
}

TorqueErrors WrenchErrors(const BodyEffectModel& model, const Eigen::VectorXd& x, const BodyLog& log) {
  CheckLog(log);
  Eigen::MatrixXd measured(log.num_pairs(), 6);
  for (int i = 0; i < log.num_pairs(); ++i) measured.row(i) = BodyEffectModel::MeasuredPair(log, i).transpose();
  return CompareTorques(model.Residuals(x, log) + measured, measured);
}

namespace {

// Held-out residuals (pairs x 6) of a model: on `validation`, or cross-validated over `train`.
struct HeldOut {
  const BodyLog* train = nullptr;
  const BodyLog* validation = nullptr;  // null: cross-validate train in `folds` blocks
  int folds = 0;
};

struct Judged {
  BodyFit fit;  // on the whole training log
  Eigen::MatrixXd residual;
  TorqueErrors errors;
  bool converged = true;
  int iterations = 0;
};

Eigen::MatrixXd Measured(const BodyLog& log) {
  Eigen::MatrixXd m(log.num_pairs(), 6);
  for (int i = 0; i < log.num_pairs(); ++i) m.row(i) = BodyEffectModel::MeasuredPair(log, i).transpose();
  return m;
}

Judged Judge(const BodyEffectModel& model, const HeldOut& h, const LevenbergMarquardtOptions& options,
             const Eigen::VectorXd& x0) {
  Judged j;
  j.fit = FitBodyModel(model, *h.train, options, x0);
  j.converged = j.fit.lm.converged();
  j.iterations = j.fit.lm.iterations;
  const BodyLog& held = h.validation != nullptr ? *h.validation : *h.train;
  if (h.validation != nullptr) {
    j.residual = model.Residuals(j.fit.x, held);
  } else {
    const int P = h.train->num_pairs();
    j.residual.resize(P, 6);
    for (int k = 0; k < h.folds; ++k) {
      const int begin = k * P / h.folds, end = (k + 1) * P / h.folds;
      std::vector<int> fitted;
      // The pair on each side of the block shares a sample with it: left out of the fit.
      for (int i = 0; i < P; ++i) {
        if (i < begin - 1 || i > end) fitted.push_back(i);
      }
      const BodyFit f = FitBodyModel(model, *h.train, options, j.fit.x, fitted);
      j.converged = j.converged && f.lm.converged();
      j.iterations += f.lm.iterations;
      const Eigen::MatrixXd r = model.Residuals(f.x, *h.train);
      j.residual.middleRows(begin, end - begin) = r.middleRows(begin, end - begin);
    }
  }
  const Eigen::MatrixXd measured = Measured(held);
  j.errors = CompareTorques(j.residual + measured, measured);
  return j;
}

BodyDiagnosis Diagnose(const InertialParams& prior, const std::vector<BodyEffectKind>& effects, const HeldOut& h,
                       const BodyDiagnosisOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  BodyDiagnosis out;
  out.effects = effects;
  out.folds = h.validation != nullptr ? 0 : h.folds;
  out.train_pairs = h.train->num_pairs();
  const BodyLog& held = h.validation != nullptr ? *h.validation : *h.train;
  out.validation_pairs = held.num_pairs();
  const BodyEffectModel base(prior, effects);
  const Judged b = Judge(base, h, options.fit, Eigen::VectorXd());
  out.fit = b.fit;
  out.fit_train = WrenchErrors(base, out.fit.x, *h.train);
  out.fit_validation = b.errors;
  out.prior_validation = WrenchErrors(base, Eigen::VectorXd::Zero(base.num_parameters()), held);
  if (!std::isfinite(out.fit_validation.total_rms) || !std::isfinite(out.prior_validation.total_rms)) {
    throw std::invalid_argument("single-body diagnosis: the model's wrenches are not finite numbers (check the data's "
                                "magnitudes and units)");
  }
  // Reported: the model's own held-out residual's correlation (candidates are judged on their own).
  out.residual_tau.resize(6);
  for (int c = 0; c < 6; ++c) out.residual_tau[c] = IntegratedAutocorrelationTime(b.residual.col(c));
  EvidenceRules rules;
  rules.min_explained = options.min_explained;
  rules.min_gain = options.min_gain;

  for (BodyEffectKind kind : {BodyEffectKind::kForceBias, BodyEffectKind::kMomentBias, BodyEffectKind::kVelocityBias,
                              BodyEffectKind::kGravity}) {
    if (std::find(effects.begin(), effects.end(), kind) != effects.end()) continue;
    std::vector<BodyEffectKind> with = effects;
    with.push_back(kind);
    const BodyEffectModel model(prior, with);
    Eigen::VectorXd x0 = Eigen::VectorXd::Zero(model.num_parameters());
    x0.head(base.num_parameters()) = out.fit.x;  // the new effect's parameters come last
    const Judged j = Judge(model, h, options.fit, x0);
    BodyCandidateResult r;
    r.kind = kind;
    r.validation = j.errors;
    // The residual's correlation is measured on what the candidate leaves (the noise, if it is the
    // missing effect), not on the model's residual, which the missing effect itself colours.
    Eigen::VectorXd tau(6);
    for (int c = 0; c < 6; ++c) tau[c] = IntegratedAutocorrelationTime(j.residual.col(c));
    r.evidence = JudgeCandidate(out.fit_validation, r.validation, tau, out.validation_pairs, 0.0, 0.0,
                                ParameterCount(kind), PriorOdds::kOrdinary, rules);
    r.explained = r.evidence.explained;
    r.converged = j.converged;
    r.iterations = j.iterations;
    r.values = model.EffectValues(static_cast<int>(with.size()) - 1, j.fit.x);
    out.candidates.push_back(r);
  }
  // Ranked as candidate_ranking.hpp says (no near-ties or alternatives measured for a single body).
  // The model's own fit on the whole log must have converged (a fold fit that did not only makes
  // its block's prediction worse, which weakens the evidence, not the judgement).
  std::vector<CandidateEvidence> evidence;
  for (const BodyCandidateResult& r : out.candidates) evidence.push_back(r.evidence);
  RankingOptions ranking;
  ranking.model_converged = b.fit.lm.converged();
  const CandidateRanking ranked = RankCandidates(evidence, ranking);
  std::vector<BodyCandidateResult> sorted;
  for (int i : ranked.order) sorted.push_back(std::move(out.candidates[i]));
  out.candidates = std::move(sorted);
  out.num_suggestions = ranked.num_suggestions;
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

}  // namespace

BodyDiagnosis DiagnoseBodyModel(const InertialParams& prior, const std::vector<BodyEffectKind>& effects,
                                const BodyLog& train, const BodyLog& validation, const BodyDiagnosisOptions& options) {
  if ((train.gravity.empty()) != (validation.gravity.empty())) {
    throw std::invalid_argument("single-body diagnosis: the training and held-out logs must both have gravity or neither");
  }
  CheckLog(train);
  CheckLog(validation);
  HeldOut h;
  h.train = &train;
  h.validation = &validation;
  return Diagnose(prior, effects, h, options);
}

BodyDiagnosis DiagnoseBodyModelCrossValidated(const InertialParams& prior, const std::vector<BodyEffectKind>& effects,
                                              const BodyLog& log, const BodyDiagnosisOptions& options) {
  CheckLog(log);
  if (options.folds < 2) {
    throw std::invalid_argument("cross-validation: " + std::to_string(options.folds) + " folds; at least 2 are needed");
  }
  if (log.num_pairs() < options.folds * kMinPairsPerFold) {
    throw std::invalid_argument("cross-validation: " + std::to_string(log.samples.size()) + " samples are too few for " +
                                std::to_string(options.folds) + " folds (at least " +
                                std::to_string(options.folds * kMinPairsPerFold + 1) + " are needed, " +
                                std::to_string(kMinPairsPerFold) + " pairs per fold)");
  }
  HeldOut h;
  h.train = &log;
  h.folds = options.folds;
  return Diagnose(prior, effects, h, options);
}

void SplitHoldout(const BodyLog& log, double fraction, BodyLog* train, BodyLog* validation) {
  if (!(fraction > 0.0 && fraction < 1.0)) throw std::invalid_argument("holdout: the fraction must be in (0, 1)");
  const int N = static_cast<int>(log.samples.size());
  const int held = static_cast<int>(std::lround(fraction * N));
  if (held < 3 || N - held < 3) {
    throw std::invalid_argument("holdout: " + std::to_string(N) + " samples cannot be split into two parts of at least 3");
  }
  train->samples.assign(log.samples.begin(), log.samples.end() - held);
  validation->samples.assign(log.samples.end() - held, log.samples.end());
  train->gravity.clear();
  validation->gravity.clear();
  if (!log.gravity.empty()) {
    train->gravity.assign(log.gravity.begin(), log.gravity.end() - held);
    validation->gravity.assign(log.gravity.end() - held, log.gravity.end());
  }
}

}  // namespace inertial
