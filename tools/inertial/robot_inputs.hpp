// The inputs `identify` and `diagnose` share: gravity, effects, the URDF robot and its model, and
// joint logs, each turned into an exit code and an `Error:` line on stderr when bad.
#pragma once

#include <optional>
#include <string>

#include "inertial/estimation/batch/joint_identification.hpp"
#include "inertial/formats/model_file.hpp"
#include "inertial/formats/joint_csv.hpp"
#include "inertial/formats/user_region.hpp"
#include "inertial/signal/recorded_runs.hpp"

namespace inertial::cli {

/// "0 0 -9.81" -> a vector; kUsage on a wrong count, kInvalidValue on a bad number.
int ParseGravityOption(const std::string& text, Vector3* gravity);

/// Loads the URDF; kInconsistentBody (with a repair hint) or kIoError on failure, the error printed.
int LoadRobotModel(const std::string& urdf, RobotModel* robot);
/// "note: N meshes of URDF not read, ..." on stderr, naming the first three (RobotModel::unread_meshes).
void PrintUnreadMeshesNote(const RobotModel& robot, const std::string& urdf);

/// Loads the URDF and builds its model with the effects the file declares (<inertial_effects>) and
/// `effects` (parsed from the --effects text; replacing a declared one of the same kind and target).
/// kInconsistentBody (with a repair hint), kIoError or kUsage on failure.
int LoadRobot(const std::string& urdf, const std::string& effects_text, const Vector3& gravity, RobotModel* robot,
              std::vector<EffectSpec>* effects, std::optional<RobotDynamics>* model);

/// The help text of --region, shared by the commands that fit.
inline constexpr const char* kRegionHelp =
    "LINK=cx,cy,cz,a,b,c[:rpy=r,p,y]: the region LINK's mass may occupy, replacing the automatic one: an ellipsoid "
    "with centre (cx,cy,cz) and semi-axes a,b,c [m] along LINK's frame axes (or, with rpy, along those axes turned "
    "by URDF roll-pitch-yaw), in LINK's frame; payload@LINK for a payload; it must hold the URDF's inertia (the fit "
    "starts there); its mass bound is solid steel over it. Give it once per link";

/// The help text of --total-mass, shared by the commands that fit.
inline constexpr const char* kTotalMassHelp =
    "the whole robot as weighed, links whose inertia is not estimated included: the fit keeps the links' masses "
    "plus the URDF masses of the links fixed to the base at most this (payloads and rotors not counted), with a "
    "barrier that acts only within 5 % of it";

/// Parses every --region item (user_region.hpp); kOk, or kUsage / kInvalidValue (a value not a finite
/// number) with the error printed, naming the item.
int ParseRegionOptions(const std::vector<std::string>& items, std::vector<UserRegion>* regions);

/// Applies the regions to *model (require_body: see ApplyUserRegions); kOk, or kUsage with the error printed.
int ApplyRegionOptions(const RobotModel& robot, const std::vector<UserRegion>& regions, RobotDynamics* model,
                       bool require_body = true);

/// --total-mass (empty: none): the bound with the URDF mass fixed to the base (MassFixedToBase), a note
/// on stderr of what it counts, into *bound. `held_links`: the links' masses are held at the URDF's
/// (diagnose --hold-links), so they must leave room too. kOk, or kUsage / kInvalidValue with the error printed.
int ParseTotalMassOption(const std::string& text, const RobotModel& robot, const RobotDynamics& model, bool held_links,
                         std::optional<TotalMassBound>* bound);

/// Reads a joint log for the robot's joints, printing the reader's notices; kIoError on failure.
/// *lines (optional) gets each sample's line in the file.
int ReadRobotLog(const std::string& path, const RobotModel& robot, const JointCsvOptions& csv, JointSamples* samples,
                 std::vector<int>* lines = nullptr);

/// A payload carried during one run: `--run-payload FILE=LINK:mass=M:com=X,Y,Z` with optionally
/// `:inertia=IXX,IYY,IZZ,IXY,IXZ,IYZ` (kg m^2 about its COM, in LINK's frame; without it, a sphere
/// of radius 1 cm: a point mass to within the torque its own rotation adds). Without com=, its COM
/// and inertia are fitted with the model (run_payload_fit.hpp), its mass held at mass= where given,
/// fitted too where not (`FILE=LINK`).
struct RunPayload {
  std::string file, link, text;
  InertialParams body;      ///< in LINK's frame: as stated, or (fitted) the fit's prior, then its result
  bool fitted = false;      ///< the COM (and inertia, and mass unless mass_known) fitted with the model
  bool mass_known = false;
  bool known = true;        ///< body holds the payload (as stated, or once fitted)
};

/// How ReadRobotRuns fits run payloads whose COM is not given (run_payload_fit.hpp).
struct RunPayloadFit {
  std::vector<EffectSpec> effects;       ///< the model's effects (joint effects, rotors, payloads)
  JointIdentificationOptions options;    ///< prior weight and Levenberg-Marquardt settings
  bool hold_links = false;               ///< links and rotors held at the model's (diagnose --hold-links)
  /// validate: every effect held at these stated values and the links at the model's, so that only
  /// the payload is fitted; empty: the effects fitted with the payload.
  std::optional<std::vector<ModelEffect>> stated_effects;
  /// The user's regions (--region), applied to the fit's model (a payload@LINK region to the
  /// model's own payload, not to a run's).
  std::vector<UserRegion> regions;
  /// The last share of each run's duration left out of the fit (diagnose: its held-out share, split
  /// as SplitRunsHoldout splits it); 0: every sample.
  double holdout = 0.0;
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

/// Payloads to be fitted (RunPayload::fitted) are fitted first, with `fit` (required then), and
/// then taken out as known ones; their bodies are written back into *payloads.
int ReadRobotRuns(const std::vector<std::string>& files, std::vector<RunPayload>* payloads, const RobotModel& robot,
                  const Vector3& gravity, const JointCsvOptions& csv, RecordedRuns* runs, std::vector<int>* lines = nullptr,
                  const LogGains& gains = {}, const RunPayloadFit* fit = nullptr);

/// The --data files as one name for messages: "a.csv" or "a.csv + b.csv".
std::string RunsName(const std::vector<std::string>& files);

}  // namespace inertial::cli
