/// @file plausibility_report.hpp
/// Each estimated body's plausibility (model/region_plausibility.hpp) as text, JSON and model-file
/// notes, the same in every command that prints or writes bodies (identify, payload, replay,
/// inertiald's model file, and validate and check for a model where no fit ran). Computes nothing
/// beyond the judgement itself.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "inertial/estimation/batch/total_mass_barrier.hpp"
#include "inertial/formats/model_plausibility.hpp"
#include "inertial/model/region_plausibility.hpp"

namespace inertial {

/// "plausible: region from drawn geometry, slack 0.42, density 1230 kg/m^3 over it, mass 1.05 x
/// the URDF's" (or "NOT plausible: ...; <words>"); the mass ratio only where it was judged
/// (RegionPlausibility::mass_compared: the prior is a drawing other than the body itself).
std::string PlausibilityText(const EstimatedBody& body, const RegionPlausibility& p);

/// {region, slack, density, mass_ratio, inside, on_edge, plausible, words}.
nlohmann::json PlausibilityJson(const EstimatedBody& body, const RegionPlausibility& p);

/// "Warning: <name>: <words>\n" for a body that is not plausible, "Note: <name>: <words>\n" for one
/// held on its region's edge, "" for the rest.
std::string PlausibilityWarning(const std::string& name, const RegionPlausibility& p);

/// PlausibilityWarning of every body (bodies in model.bodies() order, in their report frames;
/// nullopt skipped).
std::string PlausibilityWarnings(const RobotDynamics& model, const std::vector<std::optional<InertialParams>>& bodies);

/// Adds each judged body's PlausibilityText to notes[<name>] (after what is there, "; "-separated),
/// for the model file's comments.
void AddPlausibilityNotes(const RobotDynamics& model, const std::vector<std::optional<InertialParams>>& bodies,
                          std::map<std::string, std::string>* notes);

/// The section validate and check print for the bodies of a model (formats/model_plausibility.hpp):
///   Plausibility (...what the references are...)
///     <name>: <PlausibilityText> (against the recorded prior | against itself)
///   Warning: <name>: <words>                      (PlausibilityWarning of each)
/// "" if no body is judged.
std::string ModelPlausibilityText(const std::vector<JudgedBody>& judged);
/// {bodies: [{name, against, PlausibilityJson's fields}], plausible: every body plausible}.
nlohmann::json ModelPlausibilityJson(const std::vector<JudgedBody>& judged);

/// The links' total mass against the robot as weighed (--total-mass; total_mass_barrier.hpp).
struct TotalMassPlausibility {
  double links = 0.0;  ///< the model's link masses at x, summed (LinkMassSum) [kg]
  double fixed = 0.0;  ///< F: the links fixed to the base [kg]
  double bound = 0.0;  ///< M: the robot as weighed [kg]
  double slack = 1.0;  ///< r = 1 - (links + fixed) / M
  bool within = true;  ///< r >= 0: not heavier than the robot
  bool bound_acts = false;  ///< 0 <= r < kTotalMassOnset: where a fit's barrier acts
};
TotalMassPlausibility JudgeTotalMass(const RobotDynamics& model, const Eigen::VectorXd& x, const TotalMassBound& bound);

/// "Total mass: 29.1 kg of links + 2.1 kg fixed to the base = 31.2 kg against the robot's 33 kg as
/// weighed (--total-mass): within it, 5.5 % below" (", where the bound acts" within its onset), or
/// "... : NOT plausible: 229 kg is 6.94 times what the robot weighs".
std::string TotalMassText(const TotalMassPlausibility& t);
/// {links, fixed, total, bound, slack, within, bound_acts}.
nlohmann::json TotalMassJson(const TotalMassPlausibility& t);
/// "Warning: ..." (one line) when the links weigh more than the robot; "" otherwise.
std::string TotalMassWarning(const TotalMassPlausibility& t);

}  // namespace inertial
