// The inputs `identify` and `diagnose` share: gravity, effects, the URDF robot and its model, and
// joint logs, each turned into an exit code and an `Error:` line on stderr when bad.
#pragma once

#include <optional>
#include <string>

#include "inertial/io/identification_report.hpp"
#include "inertial/io/joint_csv.hpp"

namespace inertial::cli {

/// "0 0 -9.81" -> a vector; kUsage on a wrong count, kInvalidValue on a bad number.
int ParseGravityOption(const std::string& text, Vector3* gravity);

/// Loads the URDF and builds its model with `effects` (parsed from the --effects text).
/// kInconsistentBody (with a repair hint), kIoError or kUsage on failure.
int LoadRobot(const std::string& urdf, const std::string& effects_text, const Vector3& gravity, RobotModel* robot,
              std::vector<EffectSpec>* effects, std::optional<RobotDynamics>* model);

/// Reads a joint log for the robot's joints, printing the reader's notices; kIoError on failure.
int ReadRobotLog(const std::string& path, const RobotModel& robot, const JointCsvOptions& csv, JointSamples* samples);

}  // namespace inertial::cli
