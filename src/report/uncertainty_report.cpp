#include "inertial/report/uncertainty_report.hpp"

#include "inertial/report/plausibility_report.hpp"

#include <cmath>
#include <cstdio>

#include "inertial/estimation/covariance_uncertainty.hpp"
#include "inertial/estimation/fit_uncertainty.hpp"
#include "inertial/report/identification_report.hpp"
#include "inertial/model/number_text.hpp"

namespace inertial {
namespace {

constexpr const char* kInertiaNames[6] = {"Ixx", "Iyy", "Izz", "Ixy", "Iyz", "Ixz"};
constexpr const char* kAxisNames[3] = {"x", "y", "z"};

// Three significant digits; an unbounded uncertainty, of either sign, is "inf".
std::string G(double x) { return std::isinf(x) ? "inf" : FormatNumber(x, 3); }

nlohmann::json Number(double x) { return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json("inf"); }

std::string Vector(const Eigen::VectorXd& v) {
  std::string s = "[";
  for (int i = 0; i < v.size(); ++i) s += (i ? " " : "") + G(v[i]);
  return s + "]";
}

}  // namespace

ModelUncertainty FromFit(const FitUncertainty& fit) {
  ModelUncertainty u;
  u.bodies = fit.bodies;
  u.held = fit.body_held;
  u.effects = fit.effects;
  u.source = "from the fit's curvature, torque noise " + FormatNumber(fit.noise_sigma, 3) + " N m estimated from the residual";
  if (fit.time_blocks >= 2) {
    u.source += ", each at least the spread of the residual's " + std::to_string(fit.time_blocks) + " time blocks of " +
                std::to_string(fit.block_length) + " samples";
  }
  return u;
}

std::optional<ModelUncertainty> FromOnlineEstimator(const OnlineJointEstimator& estimator) {
  if (const OnlineFit* fit = estimator.fit()) {
    // One uncertainty: the batch objective's Laplace covariance at the online solution, with
    // "held by the prior", exactly as identify reports it; computed by the last solve (off the
    // estimator's lock), none before one with residual degrees of freedom.
    if (!fit->uncertainty()) return std::nullopt;
    ModelUncertainty u = FromFit(*fit->uncertainty());
    u.source = "from the curvature of the fit at its last solve, torque noise " + u.source.substr(u.source.find("noise ") + 6);
    return u;
  }
  const Eigen::MatrixXd P = estimator.estimator().Covariance();
  if (P.size() == 0) return std::nullopt;
  // The standard deviations themselves are the core's (covariance_uncertainty.hpp).
  const CovarianceUncertainty c = UncertaintyFromCovariance(estimator.model(), estimator.estimator().parameters(), P,
                                                            estimator.kind() == EstimatorKind::kLinearRls);
  ModelUncertainty u;
  u.source = "from the " + std::string(ToString(estimator.kind())) + " estimator's covariance";
  u.bodies = c.body_stds;
  u.effects = c.effects;
  return u;
}

std::vector<std::string> HeldQuantities(const BodyHeldByPrior& held) {
  std::vector<std::string> names;
  if (held.mass) names.push_back("mass");
  for (int i = 0; i < 3; ++i) {
    if (held.com[i]) names.push_back(std::string("com.") + kAxisNames[i]);
  }
  for (int i = 0; i < 6; ++i) {
    if (held.inertia_about_com[i]) names.push_back(kInertiaNames[i]);
  }
  return names;
}

std::string BodyUncertaintyText(const InertialParams& body, const BodyUncertainty& u, const BodyHeldByPrior* held) {
  const Matrix3 I = body.mass() > 0 ? body.rotational_inertia_about_com() : Matrix3::Zero();
  Vector6 inertia;
  inertia << I(0, 0), I(1, 1), I(2, 2), I(0, 1), I(1, 2), I(0, 2);
  std::string s = "mass " + G(body.mass()) + " +- " + G(u.mass) + " kg";
  if (held != nullptr && held->mass) s += " (held by the prior)";
  s += ", COM " + Vector(body.mass() > 0 ? Eigen::VectorXd(body.com()) : Eigen::VectorXd::Zero(3)) + " +- " +
       Vector(u.com) + " m, inertia about COM [Ixx Iyy Izz Ixy Iyz Ixz] " + Vector(inertia) + " +- " +
       Vector(u.inertia_about_com) + " kg m^2";
  if (held != nullptr) {
    const std::vector<std::string> names = HeldQuantities(*held);
    std::string others;
    for (const std::string& n : names) {
      if (n != "mass") others += (others.empty() ? "" : ", ") + n;
    }
    if (!others.empty()) s += "; held by the prior (the data barely determine them): " + others;
  }
  return s;
}

nlohmann::json BodyUncertaintyJson(const BodyUncertainty& u, const BodyHeldByPrior* held) {
  nlohmann::json com = nlohmann::json::array(), inertia = nlohmann::json::array();
  for (int i = 0; i < 3; ++i) com.push_back(Number(u.com[i]));
  for (int i = 0; i < 6; ++i) inertia.push_back(Number(u.inertia_about_com[i]));
  nlohmann::json j = {{"mass_std", Number(u.mass)}, {"com_std", com}, {"inertia_about_com_std", inertia}};
  j["held_by_prior"] = held != nullptr ? HeldQuantities(*held) : std::vector<std::string>{};
  return j;
}

std::map<std::string, std::string> UncertaintyNotes(const RobotDynamics& model, const ModelSnapshot& snapshot,
                                                    const ModelUncertainty& u) {
  std::map<std::string, std::string> notes;
  for (int e = 0; e < static_cast<int>(model.bodies().size()) && e < static_cast<int>(u.bodies.size()); ++e) {
    if (!snapshot.bodies[e]) continue;
    const BodyHeldByPrior* held = e < static_cast<int>(u.held.size()) ? &u.held[e] : nullptr;
    notes[model.bodies()[e].name] =
        "standard deviations (" + u.source + "): " + BodyUncertaintyText(*snapshot.bodies[e], u.bodies[e], held);
  }
  for (int k = 0; k < static_cast<int>(model.effects().size()) && k < static_cast<int>(u.effects.size()); ++k) {
    const EffectTerm& t = model.effects()[k];
    const std::vector<std::string> names = EffectValueNames(t.kind), units = EffectValueUnits(t.kind);
    std::string s;
    for (std::size_t i = 0; i < u.effects[k].size() && i < names.size(); ++i) {
      s += (i ? ", " : "") + names[i] + " = " + G(snapshot.effect_values[k][i]) + " +- " + G(u.effects[k][i]) + " " +
           units[i];
    }
    notes[std::string(ToString(t.kind)) + "@" + t.joint] = "standard deviations (" + u.source + "): " + s;
  }
  return notes;
}

ModelSnapshot SnapshotWithUncertainty(const OnlineJointEstimator& estimator) {
  ModelSnapshot snapshot = SnapshotOf(estimator);
  if (const std::optional<ModelUncertainty> u = FromOnlineEstimator(estimator)) {
    snapshot.notes = UncertaintyNotes(estimator.model(), snapshot, *u);
  }
  AddPlausibilityNotes(estimator.model(), snapshot.bodies, &snapshot.notes);
  return snapshot;
}

}  // namespace inertial
