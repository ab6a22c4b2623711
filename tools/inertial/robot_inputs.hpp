// The inputs `identify` and `diagnose` share: gravity, effects, the URDF robot and its model, and
// joint logs, each turned into an exit code and an `Error:` line on stderr when bad.
#pragma once

#include <optional>
#include <string>

#include "inertial/formats/model_file.hpp"
#include "inertial/formats/joint_csv.hpp"

namespace inertial::cli {

/// "0 0 -9.81" -> a vector; kUsage on a wrong count, kInvalidValue on a bad number.
int ParseGravityOption(const std::string& text, Vector3* gravity);

/// Loads the URDF; kInconsistentBody (with a repair hint) or kIoError on failure, the error printed.
int LoadRobotModel(const std::string& urdf, RobotModel* robot);

/// Loads the URDF and builds its model with the effects the file declares (<inertial_effects>) and
/// `effects` (parsed from the --effects text; replacing a declared one of the same kind and target).
/// kInconsistentBody (with a repair hint), kIoError or kUsage on failure.
int LoadRobot(const std::string& urdf, const std::string& effects_text, const Vector3& gravity, RobotModel* robot,
              std::vector<EffectSpec>* effects, std::optional<RobotDynamics>* model);

/// Reads a joint log for the robot's joints, printing the reader's notices; kIoError on failure.
/// *lines (optional) gets each sample's line in the file.
int ReadRobotLog(const std::string& path, const RobotModel& robot, const JointCsvOptions& csv, JointSamples* samples,
                 std::vector<int>* lines = nullptr);

}  // namespace inertial::cli
