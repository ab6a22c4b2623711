#include "inertial/estimation/body_diagnosis.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include "inertial/estimation/explained_error.hpp"

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
                     const Eigen::VectorXd& initial) {
  CheckLog(log);
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
    for (int i = 0; i < log.num_pairs(); ++i) {
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

BodyDiagnosis DiagnoseBodyModel(const InertialParams& prior, const std::vector<BodyEffectKind>& effects,
                                const BodyLog& train, const BodyLog& validation, const BodyDiagnosisOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  BodyDiagnosis out;
  out.effects = effects;
  out.train_pairs = train.num_pairs();
  out.validation_pairs = validation.num_pairs();
  if ((train.gravity.empty()) != (validation.gravity.empty())) {
    throw std::invalid_argument("single-body diagnosis: the training and held-out logs must both have gravity or neither");
  }
  const BodyEffectModel base(prior, effects);
  out.fit = FitBodyModel(base, train, options.fit);
  out.fit_train = WrenchErrors(base, out.fit.x, train);
  out.fit_validation = WrenchErrors(base, out.fit.x, validation);
  out.prior_validation = WrenchErrors(base, Eigen::VectorXd::Zero(base.num_parameters()), validation);
  if (!std::isfinite(out.fit_validation.total_rms) || !std::isfinite(out.prior_validation.total_rms)) {
    throw std::invalid_argument("single-body diagnosis: the model's wrenches are not finite numbers (check the data's "
                                "magnitudes and units)");
  }

  for (BodyEffectKind kind : {BodyEffectKind::kForceBias, BodyEffectKind::kMomentBias, BodyEffectKind::kVelocityBias,
                              BodyEffectKind::kGravity}) {
    if (std::find(effects.begin(), effects.end(), kind) != effects.end()) continue;
    std::vector<BodyEffectKind> with = effects;
    with.push_back(kind);
    const BodyEffectModel model(prior, with);
    Eigen::VectorXd x0 = Eigen::VectorXd::Zero(model.num_parameters());
    x0.head(base.num_parameters()) = out.fit.x;  // the new effect's parameters come last
    const BodyFit fit = FitBodyModel(model, train, options.fit, x0);
    BodyCandidateResult r;
    r.kind = kind;
    r.validation = WrenchErrors(model, fit.x, validation);
    r.explained = ExplainedShare(out.fit_validation.rms, r.validation.rms);
    r.converged = fit.lm.converged();
    r.iterations = fit.lm.iterations;
    r.values = model.EffectValues(static_cast<int>(with.size()) - 1, fit.x);
    out.candidates.push_back(r);
  }
  std::stable_sort(out.candidates.begin(), out.candidates.end(), [](const BodyCandidateResult& a, const BodyCandidateResult& b) {
    return RankingKey(a.explained, ParameterCount(a.kind)) > RankingKey(b.explained, ParameterCount(b.kind));
  });
  const bool converged = out.fit.lm.converged();
  const auto end = std::stable_partition(out.candidates.begin(), out.candidates.end(), [&](const BodyCandidateResult& c) {
    return SupportedByHeldOutData(out.fit_validation, c.validation, c.explained, options.min_explained,
                                  options.min_gain);
  });
  out.num_suggestions = converged ? static_cast<int>(end - out.candidates.begin()) : 0;
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
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
