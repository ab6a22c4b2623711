/// @file state_entry_names.hpp
/// The name of every entry of a robot estimator's state x (EstimatorState::x), for a model known
/// by its parameter names, as a checkpoint states it (CheckpointDescription: the model's
/// RobotDynamics::ParameterNames()). What a state saved under one model must be matched by when it
/// is carried into another (state_extension.hpp):
/// - Gauss-Newton and the gradient law estimate x itself: the names are the parameter names
///   ("thigh.alpha", ..., "rotor@hip.alpha", ..., "payload@shank.alpha", ..., "coulomb@knee.log_bc").
/// - Linear RLS estimates the coefficients w instead: the names are the feature names
///   ("thigh.m", ..., "rotor@hip.m", ..., "coulomb@knee.bc"): one pi block per tree body (links,
///   then rotors), then the effect coefficients, one per effect parameter. A payload has no entries
///   of its own there (its pi adds to its link's block), so its parameters name none.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "inertial/estimation/online/online_joint_estimator.hpp"
#include "inertial/model/robot_dynamics.hpp"

namespace inertial {

/// The names of the entries of x of an estimator of `kind` whose model has the parameters
/// `parameter_names` (in x's order), every one of which must be a parameter of `model` (the same
/// links, and the same or more effects: `model` tells what each parameter belongs to). With
/// parameter_names = model.ParameterNames(): ParameterNames(), or FeatureNames() for linear RLS.
/// Returns nullopt and sets *why (if given) naming every parameter `model` does not have.
std::optional<std::vector<std::string>> StateEntryNames(const RobotDynamics& model, EstimatorKind kind,
                                                        const std::vector<std::string>& parameter_names,
                                                        std::string* why);

}  // namespace inertial
