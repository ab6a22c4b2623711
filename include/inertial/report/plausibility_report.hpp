/// @file plausibility_report.hpp
/// Each estimated body's plausibility (model/region_plausibility.hpp) as text, JSON and model-file
/// notes, the same in every command that prints or writes bodies (identify, payload, replay,
/// inertiald's model file). Computes nothing beyond the judgement itself.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "inertial/model/region_plausibility.hpp"

namespace inertial {

/// "plausible: region from collision geometry, slack 0.42, density 1230 kg/m^3 over it, mass 1.05 x
/// the URDF's" (or "NOT plausible: ...; <words>"); the mass ratio only where the prior is drawn.
std::string PlausibilityText(const EstimatedBody& body, const RegionPlausibility& p);

/// {region, slack, density, mass_ratio, inside, on_edge, plausible, words}.
nlohmann::json PlausibilityJson(const EstimatedBody& body, const RegionPlausibility& p);

/// One line per body (bodies in model.bodies() order, in their report frames; nullopt skipped) that
/// is not plausible ("Warning: <name>: <words>") or is held on its region's edge ("Note: ...").
std::string PlausibilityWarnings(const RobotDynamics& model, const std::vector<std::optional<InertialParams>>& bodies);

/// Adds each judged body's PlausibilityText to notes[<name>] (after what is there, "; "-separated),
/// for the model file's comments.
void AddPlausibilityNotes(const RobotDynamics& model, const std::vector<std::optional<InertialParams>>& bodies,
                          std::map<std::string, std::string>* notes);

}  // namespace inertial
