// The inputs `identify` and `diagnose` share: gravity, effects, the URDF robot and its model, and
// joint logs, each turned into an exit code and an `Error:` line on stderr when bad.
#pragma once

#include <optional>
#include <string>

#include "inertial/formats/model_file.hpp"
#include "inertial/formats/joint_csv.hpp"
#include "inertial/signal/recorded_runs.hpp"

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

/// A payload carried, and known, during one run: `--run-payload FILE=LINK:mass=M:com=X,Y,Z` with
/// optionally `:inertia=IXX,IYY,IZZ,IXY,IXZ,IYZ` (kg m^2 about its COM, in LINK's frame; without
/// it, a sphere of radius 1 cm: a point mass to within the torque its own rotation adds).
struct RunPayload {
  std::string file, link, text;
  InertialParams body;  ///< in LINK's frame
};

/// Parses --run-payload items against the --data files. kUsage naming the item and what is wrong
/// (no such file among --data, no LINK, a missing mass or COM, an unknown key), kInvalidValue on a
/// bad number or an inconsistent body; the error printed.
int ParseRunPayloads(const std::vector<std::string>& items, const std::vector<std::string>& files,
                     std::vector<RunPayload>* payloads);

/// Reads every run (ReadRobotLog: each differentiated on its own), takes each known payload's
/// torques (model/body_torques.hpp) out of its run's, and lays the runs end to end
/// (signal/recorded_runs.hpp); *lines (optional) gets each sample's line in its file. kOk, or the
/// exit code (the error printed; kUsage for a payload on a link the robot does not have).
/// Torque columns that are not N m (gain@joint, joint_effect.hpp): `known_gains` (per DOF, or empty:
/// StatedLogGains) divides a column by a gain the model file states, before anything else; the DOFs in `fitted`
/// keep their log as it is (their gain is to be fitted), and a known payload's torque on them goes
/// to *known (rows = samples, columns = DOFs) instead of being taken out of the log.
struct LogGains {
  Eigen::VectorXd known_gains;
  std::vector<int> fitted;
  Eigen::MatrixXd* known = nullptr;
};

int ReadRobotRuns(const std::vector<std::string>& files, const std::vector<RunPayload>& payloads, const RobotModel& robot,
                  const Vector3& gravity, const JointCsvOptions& csv, RecordedRuns* runs, std::vector<int>* lines = nullptr,
                  const LogGains& gains = {});

/// The --data files as one name for messages: "a.csv" or "a.csv + b.csv".
std::string RunsName(const std::vector<std::string>& files);

}  // namespace inertial::cli
