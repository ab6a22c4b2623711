#include "inertial/report/plausibility_report.hpp"

#include "inertial/model/number_text.hpp"

namespace inertial {
std::string PlausibilityText(const EstimatedBody& body, const RegionPlausibility& p) {
  std::string s = std::string(p.plausible ? "plausible" : "NOT plausible") + ": region from " +
                  ToString(body.region->source) + ", slack " + FormatNumber(p.slack, 3) + ", density " +
                  FormatNumber(p.density, 4) + " kg/m^3 over it";
  if (HasDrawnPrior(body)) s += ", mass " + FormatNumber(p.mass_ratio, 3) + " x the URDF's";
  if (!p.words.empty()) s += "; " + p.words;
  return s;
}

nlohmann::json PlausibilityJson(const EstimatedBody& body, const RegionPlausibility& p) {
  nlohmann::json j = {{"region", ToString(body.region->source)},
                      {"slack", p.slack},
                      {"density", p.density},
                      {"inside", p.inside},
                      {"on_edge", p.on_edge},
                      {"plausible", p.plausible},
                      {"words", p.words}};
  j["mass_ratio"] = HasDrawnPrior(body) ? nlohmann::json(p.mass_ratio) : nlohmann::json(nullptr);
  return j;
}

std::string PlausibilityWarnings(const RobotDynamics& model, const std::vector<std::optional<InertialParams>>& bodies) {
  std::string out;
  for (size_t e = 0; e < bodies.size() && e < model.bodies().size(); ++e) {
    if (!bodies[e]) continue;
    const std::optional<RegionPlausibility> p = JudgeReportedBody(model.bodies()[e], *bodies[e]);
    if (p && !p->words.empty()) {
      out += std::string(p->plausible ? "Note: " : "Warning: ") + model.bodies()[e].name + ": " + p->words + "\n";
    }
  }
  return out;
}

void AddPlausibilityNotes(const RobotDynamics& model, const std::vector<std::optional<InertialParams>>& bodies,
                          std::map<std::string, std::string>* notes) {
  for (size_t e = 0; e < bodies.size() && e < model.bodies().size(); ++e) {
    if (!bodies[e]) continue;
    const std::optional<RegionPlausibility> p = JudgeReportedBody(model.bodies()[e], *bodies[e]);
    if (!p) continue;
    std::string& note = (*notes)[model.bodies()[e].name];
    note += (note.empty() ? "" : "; ") + PlausibilityText(model.bodies()[e], *p);
  }
}

}  // namespace inertial
