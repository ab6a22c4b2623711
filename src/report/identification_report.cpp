#include "inertial/report/identification_report.hpp"

#include "inertial/report/plausibility_report.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

#include "inertial/inertia/consistency.hpp"
#include "inertial/report/uncertainty_report.hpp"
#include "inertial/report/validation_report.hpp"
#include "inertial/model/number_text.hpp"

namespace inertial {
namespace {

double SecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}


// Principal moments (ascending) and axes (columns, right-handed) of a symmetric 3x3 tensor.
void Principal(const Matrix3& I, Vector3* moments, Matrix3* axes) {
  const Eigen::SelfAdjointEigenSolver<Matrix3> eig(I);
  *moments = eig.eigenvalues();
  *axes = eig.eigenvectors();
  if (axes->determinant() < 0) axes->col(2) *= -1.0;
}

nlohmann::json VectorJson(const Eigen::VectorXd& v) {
  nlohmann::json j = nlohmann::json::array();
  for (int i = 0; i < v.size(); ++i) j.push_back(v[i]);
  return j;
}

nlohmann::json MatrixJson(const Eigen::MatrixXd& M) {
  nlohmann::json j = nlohmann::json::array();
  for (int r = 0; r < M.rows(); ++r) j.push_back(VectorJson(M.row(r).transpose()));
  return j;
}

}  // namespace

// The unit of each value of an effect on a revolute joint (prismatic: N, m, kg).
std::vector<std::string> EffectValueUnits(EffectKind kind) {
  switch (kind) {
    case EffectKind::kViscous: return {"N m s/rad"};
    case EffectKind::kCoulomb: return {"N m"};
    case EffectKind::kOffset: return {"N m"};
    case EffectKind::kArmature: return {"kg m^2"};
    case EffectKind::kSpring: return {"N m/rad", "rad"};
    case EffectKind::kAsymmetric: return {"N m", "N m"};
    case EffectKind::kSigmoid: return {"N m"};
    default: return {};
  }
}


bool IdentificationRun::failed() const {
  return fit.lm.reason == StopReason::kNumericalFailure || !fit.x.allFinite() || !std::isfinite(fit.data_cost);
}

IdentificationRun RunIdentification(const RobotDynamics& model, const JointSamples& all_train,
                                    const JointSamples* validation, const JointIdentificationOptions& options,
                                    const OutlierOptions& outliers) {
  IdentificationRun run;
  const auto start = std::chrono::steady_clock::now();
  RobustIdentificationResult robust = IdentifyJointModelRobust(model, all_train, options, outliers);
  run.fit_seconds = SecondsSince(start);
  run.fit = std::move(robust.fit);
  run.outliers = std::move(robust.outliers);
  const JointNormalEquations& eq = robust.equations;
  const JointSamples train = run.outliers.rejected.empty()
                                 ? all_train
                                 : SelectSamples(all_train, RowsExcept(all_train.size(), run.outliers.rejected));
  run.train_samples = train.size();
  // The prior's own error: the URDF's bodies and no effects.
  const Eigen::VectorXd x_urdf = PriorParametersWithoutEffects(model);
  run.prior_weight = options.prior_weight;
  run.prior_train = CompareTorques(PredictJointTorques(model, x_urdf, train), train.tau);
  run.fit_train = CompareTorques(PredictJointTorques(model, run.fit.x, train), train.tau);
  if (validation != nullptr) {
    // Held-out rows whose measurement or prediction is not finite (a glitch in the validation log)
    // are left out of its errors and counted, as validate does.
    Eigen::MatrixXd prior = PredictJointTorques(model, x_urdf, *validation);
    Eigen::MatrixXd fitted = PredictJointTorques(model, run.fit.x, *validation);
    Eigen::MatrixXd both(prior.rows(), 2 * prior.cols());
    both << prior, fitted;
    const std::vector<int> bad = NonFiniteRows(both, *validation);
    JointSamples kept_validation;
    const JointSamples* v = validation;
    if (!bad.empty()) {
      if (static_cast<int>(bad.size()) == validation->size()) {
        throw std::invalid_argument("the validation log has no sample with finite values and predictions");
      }
      kept_validation = SelectSamples(*validation, RowsExcept(validation->size(), bad));
      v = &kept_validation;
      prior = PredictJointTorques(model, x_urdf, *v);
      fitted = PredictJointTorques(model, run.fit.x, *v);
      run.validation_left_out = static_cast<int>(bad.size());
    }
    run.validation_samples = v->size();
    run.prior_validation = CompareTorques(prior, v->tau);
    run.fit_validation = CompareTorques(fitted, v->tau);
  }
  if (!run.failed()) {
    run.identifiability = AnalyzeIdentifiability(eq.AtA, model.FeatureNames());
    try {
      // The data's part of the covariance also from time blocks (the residual's correlation in
      // time and model error; fit_uncertainty.hpp), every variance the larger of it and the
      // white-noise one.
      const TimeBlocks blocks = AccumulateTimeBlocks(model, train, run.fit.x);
      run.uncertainty =
          EstimateFitUncertainty(model, eq, run.fit.x, options.prior_weight, options.frozen_bodies, blocks);
    } catch (const std::invalid_argument& e) {
      run.uncertainty_unavailable = e.what();
    }
  }
  return run;
}

namespace {

// The report's first lines: the problem's size, how the fit stopped, the outliers left out, the cost.
void WriteFitSummary(std::ostringstream& out, const RobotDynamics& model, const IdentificationRun& run) {
  const JointIdentificationResult& fit = run.fit;
  out << "Identification (eq. 14: log-Cholesky theta relative to the URDF prior, log-det regularizer)\n";
  out << "  " << model.bodies().size() << " bodies, " << model.effects().size() << " effect terms, "
      << model.num_parameters() << " parameters; " << run.train_samples << " training samples";
  if (run.fit_validation) out << ", " << run.validation_samples << " validation samples";
  if (run.validation_left_out > 0) {
    out << " (" << run.validation_left_out << " more left out: a value or prediction not finite)";
  }
  out << "\n  Levenberg-Marquardt: " << fit.lm.iterations << " iterations, stopped on " << ToString(fit.lm.reason)
      << (fit.lm.converged() ? " (converged)" : " (NOT converged)") << ", " << FormatFixed(run.fit_seconds, 3)
      << " s with the regressor (" << run.outliers.rounds << " fit" << (run.outliers.rounds == 1 ? "" : "s")
      << " of the outlier screening)\n";
  const OutlierReport& o = run.outliers;
  if (!o.rejected.empty()) {
    out << "  outliers: " << o.rejected.size() << " of " << run.train_samples + static_cast<int>(o.rejected.size())
        << " training rows left out (" << o.non_finite.size() << " with non-finite values; the others beyond "
        << FormatNumber(o.threshold, 3) << " robust standard deviations of the residual), e.g.\n";
    for (const std::string& r : o.reasons) out << "    " << r << "\n";
  }
  if (o.rows_by_run.size() > 1) {  // each run screened by its own spread (robust_identification.hpp)
    out << "  runs (in --data order): rows left out as outliers, and the robust scale of the residual per joint\n";
    for (std::size_t r = 0; r < o.rows_by_run.size(); ++r) {
      out << "    run " << r + 1 << ": " << o.rejected_by_run[r] << " of " << o.rows_by_run[r] << " rows left out; scale";
      for (int j = 0; j < o.run_scale.cols(); ++j) out << " " << FormatNumber(o.run_scale(static_cast<Eigen::Index>(r), j), 4);
      out << " N m\n";
    }
  }
  out << "  cost: data " << FormatNumber(fit.data_cost, 6) << " N^2 m^2, regularizer " << FormatNumber(fit.regularizer, 6)
      << "\n\n";
}

// One identified body: mass, COM, inertia, principal axes, standard deviations, consistency.
// Returns whether it is physically consistent.
bool WriteBody(std::ostringstream& out, const RobotDynamics& model, const IdentificationRun& run, int e) {
  const InertialParams body = model.BodyInertia(e, run.fit.x);
  const ConsistencyReport c = CheckConsistency(body);
  const InertialParams prior = model.BodyInertia(e, Eigen::VectorXd::Zero(model.num_parameters()));
  const Vector3 com = body.com();
  const Matrix3 I = body.rotational_inertia_about_com();
  Vector3 moments;
  Matrix3 axes;
  Principal(I, &moments, &axes);
  out << "  " << model.bodies()[e].name << ": mass " << FormatNumber(body.mass(), 6) << " kg (prior "
      << FormatNumber(prior.mass(), 6) << "), COM [" << FormatNumber(com.x(), 5) << ", " << FormatNumber(com.y(), 5)
      << ", " << FormatNumber(com.z(), 5) << "] m\n";
  out << "    inertia about COM [Ixx Iyy Izz Ixy Iyz Ixz] = [" << FormatNumber(I(0, 0), 5) << " "
      << FormatNumber(I(1, 1), 5) << " " << FormatNumber(I(2, 2), 5) << " " << FormatNumber(I(0, 1), 5) << " "
      << FormatNumber(I(1, 2), 5) << " " << FormatNumber(I(0, 2), 5) << "] kg m^2\n";
  out << "    principal moments [" << FormatNumber(moments[0], 5) << " " << FormatNumber(moments[1], 5) << " "
      << FormatNumber(moments[2], 5) << "] kg m^2 about axes";
  for (int k = 0; k < 3; ++k) {
    out << " (" << FormatFixed(axes(0, k), 3) << " " << FormatFixed(axes(1, k), 3) << " " << FormatFixed(axes(2, k), 3)
        << ")";
  }
  out << "\n";
  if (run.uncertainty) {
    out << "    +- " << BodyUncertaintyText(body, run.uncertainty->bodies[e], &run.uncertainty->body_held[e]) << "\n";
  }
  out << "    " << (c.fully_consistent() ? "physically consistent" : "NOT physically consistent: " + c.reason)
      << " (mass " << FormatNumber(c.mass, 3) << " kg, triangle margin " << FormatNumber(c.min_triangle_margin, 3)
      << " kg m^2, min eig J " << FormatNumber(c.min_pseudo_inertia_eigenvalue, 3) << ")\n";
  if (const auto p = JudgeEstimatedBody(model.bodies()[e], run.fit.x.segment<10>(10 * e))) {
    out << "    " << PlausibilityText(model.bodies()[e], *p) << "\n";
  }
  return c.fully_consistent();
}

// The bodies' section; returns whether every body is physically consistent.
bool WriteBodies(std::ostringstream& out, const RobotDynamics& model, const IdentificationRun& run) {
  bool all_consistent = true;
  out << "Bodies (each in its own link frame; inertia about the COM)";
  if (run.uncertainty) {
    const FitUncertainty& u = *run.uncertainty;
    out << "; +- one standard deviation from the fit's curvature with the torque noise estimated from the residual ("
        << FormatNumber(u.noise_sigma, 4) << " N m)";
    if (u.time_blocks >= 2) {
      out << ", each the larger of that and the spread of the residual's " << u.time_blocks << " time blocks of "
          << u.block_length << " samples (the residual is correlated over " << FormatNumber(u.correlation_time, 3)
          << " samples; the blocks' std is up to " << FormatNumber(u.max_block_to_white_ratio, 3)
          << " times the white-noise one)";
    }
    out << "; \"held by the prior\": the data determine it less than the regularizer does";
  } else if (!run.uncertainty_unavailable.empty()) {
    out << "; no standard deviations: " << run.uncertainty_unavailable;
  }
  out << "\n";
  for (int e = 0; e < static_cast<int>(model.bodies().size()); ++e) {
    const bool consistent = WriteBody(out, model, run, e);
    all_consistent = all_consistent && consistent;
  }
  // What a user must not miss, once more after the numbers: bodies no link could be, or held by
  // their regions.
  std::vector<std::optional<InertialParams>> fitted;
  for (int e = 0; e < static_cast<int>(model.bodies().size()); ++e) fitted.push_back(model.BodyInertia(e, run.fit.x));
  out << PlausibilityWarnings(model, fitted);
  return all_consistent;
}

// The effects' section (none without effect terms): each value with its standard deviation and unit.
void WriteEffects(std::ostringstream& out, const RobotDynamics& model, const IdentificationRun& run) {
  if (model.effects().empty()) return;
  out << "\nEffects\n";
  for (int k = 0; k < static_cast<int>(model.effects().size()); ++k) {
    const EffectTerm& t = model.effects()[k];
    const std::vector<double> v = model.EffectValues(k, run.fit.x);
    const std::vector<std::string> names = EffectValueNames(t.kind), units = EffectValueUnits(t.kind);
    out << "  " << ToString(t.kind) << "@" << t.joint << ":";
    for (size_t i = 0; i < v.size(); ++i) {
      out << " " << names[i] << " = " << FormatNumber(v[i], 6);
      if (run.uncertainty) out << " +- " << FormatNumber(run.uncertainty->effects[k][i], 3);
      out << " " << units[i];
    }
    out << "\n";
  }
}

// The torque errors on one data set, per joint and over all, of the prior and of the identified model.
void WriteTorqueErrors(std::ostringstream& out, const RobotDynamics& model, const char* what, const TorqueErrors& prior,
                       const TorqueErrors& fitted) {
  out << "\nTorque error on " << what << " data: RMS [N m] (relative RMS), URDF prior -> identified\n";
  for (int k = 0; k < model.num_dofs(); ++k) {
    out << "  " << model.dof_names()[k] << ": " << FormatNumber(prior.rms[k], 4) << " ("
        << FormatFixed(100 * prior.relative_rms[k], 1) << " %) -> " << FormatNumber(fitted.rms[k], 4) << " ("
        << FormatFixed(100 * fitted.relative_rms[k], 1) << " %)\n";
  }
  out << "  all joints: " << FormatNumber(prior.total_rms, 4) << " (" << FormatFixed(100 * prior.total_relative_rms, 1)
      << " %) -> " << FormatNumber(fitted.total_rms, 4) << " (" << FormatFixed(100 * fitted.total_relative_rms, 1)
      << " %)\n";
}

// The identifiability section: the rank, and the first max_directions directions the data do not see.
void WriteIdentifiability(std::ostringstream& out, const IdentifiabilityReport& id, int max_directions) {
  out << "\nIdentifiability: " << id.rank << " of " << id.num_parameters
      << " regressor columns identified (condition number " << FormatNumber(id.condition_number, 3) << ")";
  if (id.directions.empty()) {
    out << "; every direction is excited\n";
  } else {
    out << "; the data do not see " << id.directions.size()
        << " directions (the regularizer keeps them at the prior):\n";
    for (int k = 0; k < static_cast<int>(id.directions.size()) && k < max_directions; ++k) {
      out << "  - " << id.directions[k].description << "\n";
    }
    if (static_cast<int>(id.directions.size()) > max_directions) {
      out << "  ... and " << id.directions.size() - max_directions << " more (see --json)\n";
    }
  }
}

// Each base combination's value at the fit, its std (nullopt without the fit's uncertainty) and
// whether the prior holds it.
struct CombinationEstimate {
  double value = 0;
  std::optional<double> std;
  bool held_by_prior = false;
};

std::vector<CombinationEstimate> EstimateCombinations(const RobotDynamics& model, const IdentificationRun& run) {
  std::vector<CombinationEstimate> estimates;
  const std::vector<BaseCombination>& combinations = run.identifiability.base_combinations;
  if (combinations.empty()) return estimates;
  const Eigen::VectorXd w = model.Coefficients(run.fit.x);
  for (const BaseCombination& c : combinations) {
    const Eigen::VectorXd k = c.Vector(static_cast<int>(w.size()));
    CombinationEstimate e;
    e.value = k.dot(w);
    if (run.uncertainty) {
      const CombinationUncertainty u = UncertaintyOfCombination(run.uncertainty->coefficients, k);
      e.std = u.std;
      e.held_by_prior = u.held_by_prior;
    }
    estimates.push_back(e);
  }
  return estimates;
}

// A text report is read by a person: past a screenful the list buries the rest of the report, and
// the combinations the data determine well carry no news. The least certain ones are those a
// reader acts on (more excitation, or a question of what the model lacks); --json has them all.
constexpr int kMaxCombinationLines = 30;

// The identifiable combinations: each with its value and std, at most kMaxCombinationLines of
// them (the least certain, by std relative to the value), listed in column order.
void WriteBaseCombinations(std::ostringstream& out, const RobotDynamics& model, const IdentificationRun& run) {
  const IdentifiabilityReport& id = run.identifiability;
  if (id.num_parameters == 0) return;  // not analysed (the fit failed)
  const std::vector<BaseCombination>& combinations = id.base_combinations;
  const std::vector<CombinationEstimate> estimates = EstimateCombinations(model, run);
  const int count = static_cast<int>(combinations.size());
  out << "\nIdentifiable combinations (base parameters): " << count << " of " << id.num_parameters
      << ", what the torques determine (each an independent coefficient plus the dependent ones regrouped into it,"
      << " in the first one's units; value";
  if (run.uncertainty) out << " +- one standard deviation of the fit";
  out << ")";
  std::vector<int> shown(count);
  for (int i = 0; i < count; ++i) shown[i] = i;
  if (count > kMaxCombinationLines) {
    if (run.uncertainty) {
      auto relative = [&](int i) {
        const double sd = *estimates[i].std, v = std::abs(estimates[i].value);
        return sd == 0.0 ? 0.0 : v > 0.0 ? sd / v : std::numeric_limits<double>::infinity();
      };
      std::stable_sort(shown.begin(), shown.end(), [&](int a, int b) { return relative(a) > relative(b); });
      out << "; the " << kMaxCombinationLines << " least certain (largest std relative to the value)";
    } else {
      out << "; the first " << kMaxCombinationLines;
    }
    shown.resize(kMaxCombinationLines);
    std::sort(shown.begin(), shown.end());
  }
  out << ":\n";
  for (int i : shown) {
    const CombinationEstimate& e = estimates[i];
    out << "  " << combinations[i].text << " = " << FormatNumber(e.value, 4);
    if (e.std) out << " +- " << FormatNumber(*e.std, 3);
    if (e.held_by_prior) out << " (held by the prior)";
    out << "\n";
  }
  if (count > kMaxCombinationLines) out << "  ... and " << count - kMaxCombinationLines << " more (see --json)\n";
}

}  // namespace

std::string IdentificationText(const RobotDynamics& model, const IdentificationRun& run, int max_directions) {
  std::ostringstream out;
  WriteFitSummary(out, model, run);
  const bool all_consistent = WriteBodies(out, model, run);
  WriteEffects(out, model, run);
  WriteTorqueErrors(out, model, "training", run.prior_train, run.fit_train);
  if (run.fit_validation) WriteTorqueErrors(out, model, "validation", *run.prior_validation, *run.fit_validation);
  WriteIdentifiability(out, run.identifiability, max_directions);
  WriteBaseCombinations(out, model, run);
  out << "\n" << (all_consistent ? "Every identified body is physically consistent."
                                 : "SOME IDENTIFIED BODY IS NOT PHYSICALLY CONSISTENT (a bug: please report).")
      << "\n";
  return out.str();
}

nlohmann::json BodiesJson(const RobotDynamics& model, const Eigen::VectorXd& x, bool* all_consistent) {
  bool consistent = true;
  nlohmann::json bodies = nlohmann::json::array();
  for (int e = 0; e < static_cast<int>(model.bodies().size()); ++e) {
    const InertialParams body = model.BodyInertia(e, x);
    const ConsistencyReport c = CheckConsistency(body);
    consistent = consistent && c.fully_consistent();
    const Matrix3 I = body.rotational_inertia_about_com();
    Vector3 moments;
    Matrix3 axes;
    Principal(I, &moments, &axes);
    nlohmann::json b;
    b["name"] = model.bodies()[e].name;
    b["mass"] = body.mass();
    b["com"] = VectorJson(body.com());
    b["inertia_about_com"] = MatrixJson(I);
    b["principal_moments"] = VectorJson(moments);
    b["principal_axes"] = MatrixJson(axes);
    b["pi"] = VectorJson(body.vector());
    b["theta"] = VectorJson(x.segment<10>(10 * e));
    b["consistency"] = {{"mass", c.mass},
                        {"min_inertia_eigenvalue_com", c.min_inertia_eigenvalue_com},
                        {"min_triangle_margin", c.min_triangle_margin},
                        {"min_pseudo_inertia_eigenvalue", c.min_pseudo_inertia_eigenvalue}};
    b["physically_consistent"] = c.fully_consistent();
    if (const auto p = JudgeEstimatedBody(model.bodies()[e], x.segment<10>(10 * e))) {
      b["plausibility"] = PlausibilityJson(model.bodies()[e], *p);
    }
    bodies.push_back(b);
  }
  if (all_consistent != nullptr) *all_consistent = consistent;
  return bodies;
}

nlohmann::json EffectsJson(const RobotDynamics& model, const Eigen::VectorXd& x) {
  nlohmann::json effects = nlohmann::json::array();
  for (int k = 0; k < static_cast<int>(model.effects().size()); ++k) {
    const EffectTerm& t = model.effects()[k];
    const std::vector<double> v = model.EffectValues(k, x);
    const std::vector<std::string> names = EffectValueNames(t.kind);
    nlohmann::json values = nlohmann::json::object();
    for (size_t i = 0; i < v.size(); ++i) values[names[i]] = v[i];
    EffectSpec spec;
    spec.kind = t.kind;
    spec.target = t.joint;
    spec.velocity_scale = t.velocity_scale;
    spec.steepness = t.steepness;
    spec.shift = t.shift;
    effects.push_back({{"effect", std::string(ToString(t.kind))},
                       {"joint", t.joint},
                       {"item", EffectItem(spec)},
                       {"values", values}});
  }
  return effects;
}

nlohmann::json PerJointJson(const RobotDynamics& model, const Eigen::VectorXd& per_joint, double total) {
  nlohmann::json j = nlohmann::json::object();
  for (int k = 0; k < model.num_dofs(); ++k) j[model.dof_names()[k]] = per_joint[k];
  j["total"] = total;
  return j;
}

nlohmann::json IdentificationJson(const RobotDynamics& model, const IdentificationRun& run) {
  const JointIdentificationResult& fit = run.fit;
  nlohmann::json j;
  j["iterations"] = fit.lm.iterations;
  j["stop_reason"] = std::string(ToString(fit.lm.reason));
  j["converged"] = fit.lm.converged();
  j["fit_seconds"] = run.fit_seconds;
  j["prior_weight"] = run.prior_weight;
  j["train_samples"] = run.train_samples;
  j["cost"] = {{"data", fit.data_cost}, {"regularizer", fit.regularizer}};
  j["rms_train"] = PerJointJson(model, run.fit_train.rms, run.fit_train.total_rms);
  j["relative_rms_train"] = PerJointJson(model, run.fit_train.relative_rms, run.fit_train.total_relative_rms);
  j["rms_prior_train"] = PerJointJson(model, run.prior_train.rms, run.prior_train.total_rms);
  j["relative_rms_prior_train"] = PerJointJson(model, run.prior_train.relative_rms, run.prior_train.total_relative_rms);
  if (run.fit_validation) {
    j["validation_samples"] = run.validation_samples;
    j["validation_left_out"] = run.validation_left_out;
    j["rms_validation"] = PerJointJson(model, run.fit_validation->rms, run.fit_validation->total_rms);
    j["relative_rms_validation"] =
        PerJointJson(model, run.fit_validation->relative_rms, run.fit_validation->total_relative_rms);
    j["rms_prior_validation"] = PerJointJson(model, run.prior_validation->rms, run.prior_validation->total_rms);
    j["relative_rms_prior_validation"] =
        PerJointJson(model, run.prior_validation->relative_rms, run.prior_validation->total_relative_rms);
  }
  bool all_consistent = true;
  j["bodies"] = BodiesJson(model, fit.x, &all_consistent);
  j["effects"] = EffectsJson(model, fit.x);
  if (run.uncertainty) {
    j["noise_sigma"] = run.uncertainty->noise_sigma;
    j["effective_parameters"] = run.uncertainty->effective_parameters;
    j["uncertainty_blocks"] = {{"blocks", run.uncertainty->time_blocks},
                               {"block_length", run.uncertainty->block_length},
                               {"correlation_time", run.uncertainty->correlation_time},
                               {"max_block_to_white_ratio", run.uncertainty->max_block_to_white_ratio}};
    for (int e = 0; e < static_cast<int>(model.bodies().size()); ++e) {
      j["bodies"][e]["uncertainty"] = BodyUncertaintyJson(run.uncertainty->bodies[e], &run.uncertainty->body_held[e]);
    }
    for (int k = 0; k < static_cast<int>(model.effects().size()); ++k) {
      const std::vector<std::string> names = EffectValueNames(model.effects()[k].kind);
      nlohmann::json stds = nlohmann::json::object();
      for (std::size_t i = 0; i < names.size(); ++i) {
        const double sd = run.uncertainty->effects[k][i];
        stds[names[i]] = std::isfinite(sd) ? nlohmann::json(sd) : nlohmann::json("inf");
      }
      j["effects"][k]["std"] = stds;
    }
  }
  const OutlierReport& o = run.outliers;
  nlohmann::json scale = nlohmann::json::object();
  for (int k = 0; k < model.num_dofs() && k < o.scale.size(); ++k) scale[model.dof_names()[k]] = o.scale[k];
  j["outliers"] = {{"rejected", o.rejected.size()},
                   {"non_finite", o.non_finite.size()},
                   {"rows", std::vector<int>(o.rejected.begin(), o.rejected.begin() + std::min<std::size_t>(20, o.rejected.size()))},
                   {"threshold", o.threshold},
                   {"scale", scale},
                   {"rounds", o.rounds},
                   {"reasons", o.reasons}};
  if (o.rows_by_run.size() > 1) {
    nlohmann::json by_run = nlohmann::json::array();
    for (std::size_t r = 0; r < o.rows_by_run.size(); ++r) {
      nlohmann::json s = nlohmann::json::object();
      for (int k = 0; k < model.num_dofs() && k < o.run_scale.cols(); ++k) {
        s[model.dof_names()[static_cast<std::size_t>(k)]] = o.run_scale(static_cast<Eigen::Index>(r), k);
      }
      by_run.push_back({{"rows", o.rows_by_run[r]}, {"rejected", o.rejected_by_run[r]}, {"scale", s}});
    }
    j["outliers"]["by_run"] = by_run;
  }
  j["physically_consistent"] = all_consistent;
  bool all_plausible = true;
  for (const auto& b : j["bodies"]) {
    if (b.contains("plausibility") && !b["plausibility"]["plausible"].get<bool>()) all_plausible = false;
  }
  j["plausible"] = all_plausible;
  const IdentifiabilityReport& id = run.identifiability;
  nlohmann::json directions = nlohmann::json::array();
  for (const UnidentifiedDirection& d : id.directions) {
    nlohmann::json terms = nlohmann::json::object();
    for (const auto& [name, coefficient] : d.terms) terms[name] = coefficient;
    directions.push_back({{"description", d.description}, {"terms", terms}});
  }
  j["unidentified"] = {{"rank", id.rank},
                       {"parameters", id.num_parameters},
                       {"condition_number", id.condition_number},
                       {"directions", directions}};
  nlohmann::json combinations = nlohmann::json::array();
  const std::vector<CombinationEstimate> estimates = EstimateCombinations(model, run);
  for (size_t i = 0; i < id.base_combinations.size(); ++i) {
    const BaseCombination& c = id.base_combinations[i];
    nlohmann::json terms = nlohmann::json::array();
    for (const auto& [name, coefficient] : c.terms) terms.push_back(nlohmann::json::array({name, coefficient}));
    const CombinationEstimate& e = estimates[i];
    nlohmann::json sd = nullptr;
    if (e.std) sd = std::isfinite(*e.std) ? nlohmann::json(*e.std) : nlohmann::json("inf");
    combinations.push_back(
        {{"terms", terms}, {"text", c.text}, {"value", e.value}, {"std", sd}, {"held_by_prior", e.held_by_prior}});
  }
  j["base_combinations"] = combinations;
  j["x"] = VectorJson(fit.x);
  return j;
}

}  // namespace inertial
