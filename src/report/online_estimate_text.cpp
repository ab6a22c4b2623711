#include "inertial/report/online_estimate_text.hpp"

#include <cmath>
#include <optional>
#include <sstream>

#include "inertial/report/identification_report.hpp"
#include "inertial/report/plausibility_report.hpp"
#include "inertial/report/uncertainty_report.hpp"

namespace inertial {

std::string OnlineEstimateText(const OnlineJointEstimator& estimator) {
  const std::optional<ModelUncertainty> uncertainty = FromOnlineEstimator(estimator);
  const auto& bodies = estimator.model().bodies();
  std::ostringstream out;
  out << "final estimate" << (uncertainty ? " (+- one standard deviation " + uncertainty->source + ")" : "") << ":\n";
  for (int e = 0; e < static_cast<int>(bodies.size()); ++e) {
    const InertialParams b = estimator.Body(e);
    if (uncertainty) {
      const BodyHeldByPrior* held = uncertainty->held.empty() ? nullptr : &uncertainty->held[e];
      out << "  " << bodies[e].name << ": " << BodyUncertaintyText(b, uncertainty->bodies[e], held) << "\n";
    } else {
      out << "  " << bodies[e].name << ": mass " << b.mass() << " kg, COM [" << b.com().transpose() << "] m\n";
    }
    if (const std::optional<RegionPlausibility> p = JudgeReportedBody(bodies[e], b)) {
      out << "    " << PlausibilityText(bodies[e], *p) << "\n";
    }
  }
  std::vector<std::optional<InertialParams>> estimate;
  for (int e = 0; e < static_cast<int>(bodies.size()); ++e) estimate.push_back(estimator.Body(e));
  out << PlausibilityWarnings(estimator.model(), estimate);
  return out.str();
}

nlohmann::json OnlineEstimateJson(const OnlineJointEstimator& estimator) {
  const RobotDynamics& model = estimator.model();
  nlohmann::json j = {{"estimator", std::string(ToString(estimator.kind()))}};
  if (estimator.kind() == EstimatorKind::kLinearRls) return j;  // no per-body parameters
  const Eigen::VectorXd& x = estimator.estimator().parameters();
  j["bodies"] = BodiesJson(model, x);
  j["effects"] = EffectsJson(model, x);
  if (const std::optional<ModelUncertainty> u = FromOnlineEstimator(estimator)) {
    j["uncertainty_source"] = u->source;
    for (int e = 0; e < static_cast<int>(model.bodies().size()); ++e) {
      j["bodies"][e]["uncertainty"] = BodyUncertaintyJson(u->bodies[e], u->held.empty() ? nullptr : &u->held[e]);
    }
    for (int k = 0; k < static_cast<int>(model.effects().size()) && k < static_cast<int>(u->effects.size()); ++k) {
      const std::vector<std::string> names = EffectValueNames(model.effects()[k].kind);
      nlohmann::json stds = nlohmann::json::object();
      for (std::size_t i = 0; i < names.size() && i < u->effects[k].size(); ++i) {
        const double sd = u->effects[k][i];
        stds[names[i]] = std::isfinite(sd) ? nlohmann::json(sd) : nlohmann::json("inf");
      }
      j["effects"][k]["std"] = stds;
    }
  }
  if (const OnlineFit* fit = estimator.fit()) {
    nlohmann::json noise = nlohmann::json::object();
    for (int k = 0; k < model.num_dofs(); ++k) noise[model.dof_names()[k]] = fit->noise()[k];
    j["noise"] = noise;
    j["solves"] = fit->solves();
  }
  return j;
}

}  // namespace inertial
