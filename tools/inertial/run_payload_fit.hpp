// Run payloads whose COM the user did not give (`--run-payload FILE=LINK:mass=M` or `FILE=LINK`),
// fitted with the model on every run at once before anything else reads the runs.
#pragma once

#include <string>
#include <vector>

#include "robot_inputs.hpp"

namespace inertial::cli {

/// Fits every payload not yet known (RunPayload::known false) as a body of its run only (run_local_bodies.hpp): the
/// model's links, rotors and effects shared by every run (fitted, or held as `fit` says), the
/// payload's COM and inertia (and mass unless stated, else held exactly) fitted. `logs` are the runs
/// with their torque columns in N m except those in `gain_dofs` (a log whose gain is fitted with
/// them); `known[k]` the torques of run k's known payloads. Writes each fitted body (in its link's
/// frame) into *payloads and prints it. kOk, or the exit code (the error printed): kUsage for a
/// payload on a link the robot does not have or a torque scale nothing fixes, kInvalidValue if the
/// fit fails.
int FitRunPayloads(const std::vector<std::string>& files, const std::vector<JointSamples>& logs,
                   const std::vector<Eigen::MatrixXd>& known, const RobotModel& robot, const Vector3& gravity,
                   const RunPayloadFit& fit, const std::vector<int>& gain_dofs, std::vector<RunPayload>* payloads);

}  // namespace inertial::cli
