/// @file torque_predictions.hpp
/// A model's joint torques predicted for every sample of a log, written as CSV (`identify
/// --predictions`): columns t, tau_hat_<joint> for each DOF in the model's order.
#pragma once

#include <string>
#include <vector>

#include "inertial/estimation/batch/joint_identification.hpp"

namespace inertial {

/// The header: "t", then "tau_hat_<joint>" for every DOF of `model`.
std::vector<std::string> TorquePredictionHeader(const RobotDynamics& model);

/// Writes t and the torques `model` at parameters `x` predicts for every sample of `data`.
/// @throws CsvError if the file cannot be written.
void WriteTorquePredictions(const std::string& path, const RobotDynamics& model, const Eigen::VectorXd& x,
                            const JointSamples& data);

}  // namespace inertial
