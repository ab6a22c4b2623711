#include "inertial/estimation/online/state_entry_names.hpp"

#include <map>

namespace inertial {

std::optional<std::vector<std::string>> StateEntryNames(const RobotDynamics& model, EstimatorKind kind,
                                                        const std::vector<std::string>& parameter_names,
                                                        std::string* why) {
  // The entry each of model's parameters names: itself, or for linear RLS the feature it maps to
  // one to one (empty for a payload's, which has none).
  const std::vector<std::string> parameters = model.ParameterNames();
  std::map<std::string, std::string> entry;
  if (kind != EstimatorKind::kLinearRls) {
    for (const std::string& p : parameters) entry[p] = p;
  } else {
    const std::vector<std::string> features = model.FeatureNames();
    for (size_t e = 0; e < model.bodies().size(); ++e) {
      const EstimatedBody& body = model.bodies()[e];
      const bool own_block = model.tree().body_name(body.tree_body) == body.name;  // a link or a rotor, not a payload
      for (int i = 0; i < 10; ++i) {
        entry[parameters[10 * e + static_cast<size_t>(i)]] =
            own_block ? features[static_cast<size_t>(10 * body.tree_body + i)] : std::string();
      }
    }
    for (const EffectTerm& t : model.effects()) {
      for (int i = 0; i < t.size(); ++i) {
        entry[parameters[static_cast<size_t>(t.first_parameter + i)]] = features[static_cast<size_t>(t.first_feature + i)];
      }
    }
  }
  std::vector<std::string> names;
  std::string missing;
  for (const std::string& p : parameter_names) {
    const auto it = entry.find(p);
    if (it == entry.end()) {
      missing += (missing.empty() ? "'" : ", '") + p + "'";
    } else if (!it->second.empty()) {
      names.push_back(it->second);
    }
  }
  if (!missing.empty()) {
    if (why != nullptr) *why = "this model has no parameter " + missing;
    return std::nullopt;
  }
  return names;
}

}  // namespace inertial
