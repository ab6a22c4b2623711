#include "inertial/report/plausibility_report.hpp"

#include "inertial/model/number_text.hpp"

namespace inertial {
std::string PlausibilityText(const EstimatedBody& body, const RegionPlausibility& p) {
  std::string s = std::string(p.plausible ? "plausible" : "NOT plausible") + ": region from " +
                  ToString(body.region->source) + ", slack " + FormatNumber(p.slack, 3) + ", density " +
                  FormatNumber(p.density, 4) + " kg/m^3 over it";
  if (p.mass_compared) s += ", mass " + FormatNumber(p.mass_ratio, 3) + " x the URDF's";
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
  j["mass_ratio"] = p.mass_compared ? nlohmann::json(p.mass_ratio) : nlohmann::json(nullptr);
  return j;
}

std::string PlausibilityWarning(const std::string& name, const RegionPlausibility& p) {
  if (p.words.empty()) return "";
  return std::string(p.plausible ? "Note: " : "Warning: ") + name + ": " + p.words + "\n";
}

std::string PlausibilityWarnings(const RobotDynamics& model, const std::vector<std::optional<InertialParams>>& bodies) {
  std::string out;
  for (size_t e = 0; e < bodies.size() && e < model.bodies().size(); ++e) {
    if (!bodies[e]) continue;
    const std::optional<RegionPlausibility> p = JudgeReportedBody(model.bodies()[e], *bodies[e]);
    if (p) out += PlausibilityWarning(model.bodies()[e].name, *p);
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

std::string ModelPlausibilityText(const std::vector<JudgedBody>& judged) {
  if (judged.empty()) return "";
  bool recorded = false, itself = false;
  for (const JudgedBody& j : judged) (j.against_recorded_prior ? recorded : itself) = true;
  std::string out = "Plausibility (";
  if (recorded) out += "links against the URDF priors the model file records, as the fit that wrote it judged them";
  if (itself) {
    out += std::string(recorded ? "; the other bodies" : "each body") +
           " its own reference: against its collision shapes alone where it has them, else by its density over its "
           "segment region";
  }
  out += ")\n";
  for (const JudgedBody& j : judged) {
    out += "  " + j.name + ": " + PlausibilityText(j.reference, j.plausibility) + " (against " + ReferenceName(j) + ")\n";
  }
  for (const JudgedBody& j : judged) out += PlausibilityWarning(j.name, j.plausibility);
  return out;
}

nlohmann::json ModelPlausibilityJson(const std::vector<JudgedBody>& judged) {
  nlohmann::json bodies = nlohmann::json::array();
  bool plausible = true;
  for (const JudgedBody& j : judged) {
    nlohmann::json b = {{"name", j.name}, {"against", ReferenceName(j)}};
    b.update(PlausibilityJson(j.reference, j.plausibility));
    bodies.push_back(b);
    plausible = plausible && j.plausibility.plausible;
  }
  return {{"bodies", bodies}, {"plausible", plausible}};
}

TotalMassPlausibility JudgeTotalMass(const RobotDynamics& model, const Eigen::VectorXd& x, const TotalMassBound& bound) {
  TotalMassPlausibility t;
  t.links = LinkMassSum(model, x);
  t.fixed = bound.fixed;
  t.bound = bound.total;
  t.slack = 1.0 - (t.links + t.fixed) / t.bound;
  t.within = t.slack >= 0.0;
  t.bound_acts = t.within && t.slack < kTotalMassOnset;
  return t;
}

std::string TotalMassText(const TotalMassPlausibility& t) {
  const double total = t.links + t.fixed;
  std::string s = "Total mass: " + FormatNumber(t.links, 4) + " kg of links";
  if (t.fixed > 0.0) s += " + " + FormatNumber(t.fixed, 4) + " kg fixed to the base = " + FormatNumber(total, 4) + " kg";
  s += " against the robot's " + FormatNumber(t.bound, 4) + " kg as weighed (--total-mass): ";
  if (t.within) {
    s += "within it, " + FormatNumber(100.0 * t.slack, 3) + " % below";
    if (t.bound_acts) s += " (within " + FormatNumber(100.0 * kTotalMassOnset, 2) + " % of it, where the bound acts on a fit)";
  } else {
    s += "NOT plausible: " + FormatNumber(total, 4) + " kg is " + FormatNumber(total / t.bound, 3) +
         " times what the robot weighs";
  }
  return s + "\n";
}

nlohmann::json TotalMassJson(const TotalMassPlausibility& t) {
  return {{"links", t.links},   {"fixed", t.fixed},   {"total", t.links + t.fixed}, {"bound", t.bound},
          {"slack", t.slack},   {"within", t.within}, {"bound_acts", t.bound_acts}};
}

std::string TotalMassWarning(const TotalMassPlausibility& t) {
  if (t.within) return "";
  return "Warning: the links weigh " + FormatNumber(t.links + t.fixed, 4) + " kg, more than the " +
         FormatNumber(t.bound, 4) + " kg the robot weighs (--total-mass): some link's mass is wrong (a typing error, "
         "a payload or friction explained with mass)\n";
}

}  // namespace inertial
