/// @file model_file.hpp
/// A robot model with its values as one URDF file (the format is in urdf_model.hpp: links'
/// <inertial>, joints' <dynamics>, and <inertial_effects> for the rest), written by `identify
/// --write-urdf`, `replay --write-urdf`, `inertiald --write-urdf` and `inertial export`, and read
/// back by `validate --model` to the same predictions (numbers written with %.17g).
///
/// Estimated bodies map to the file as follows: a URDF link's tree body -> that link's <inertial>
/// (the inertials of links merged into it by fixed joints removed: the body's whole inertia is on
/// its link); a rotor -> <rotor> (in the rotor frame); a payload -> <payload> (in its link's frame).
/// Conventions: pi order of types.hpp, SI units.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "inertial/estimation/online/online_joint_estimator.hpp"
#include "inertial/formats/urdf_model.hpp"
#include "inertial/model/robot_dynamics.hpp"

namespace inertial {

/// A model's values: every estimated body and every effect term's coefficients.
struct ModelSnapshot {
  /// Per estimated body (RobotDynamics::bodies() order) in its report frame; nullopt: merged into
  /// its link's body (a payload under linear RLS, which estimates tree bodies only).
  std::vector<std::optional<InertialParams>> bodies;
  /// Per effect term (RobotDynamics::effects() order): RobotDynamics::EffectValues order.
  std::vector<std::vector<double>> effect_values;
  /// A comment for a body ("thigh", "rotor@hip", "payload@tool0") or effect ("coulomb@knee").
  std::map<std::string, std::string> notes;
  /// Effects of the log rather than of the dynamics (gain@joint with its value), written after the
  /// model's own.
  std::vector<ModelEffect> measurement;
};

/// Per DOF of the robot: the gain of its torque column that `effects` state (gain@joint with a
/// value, joint_effect.hpp), 1 where none; empty if none is stated.
Eigen::VectorXd StatedLogGains(const RobotModel& robot, const std::vector<ModelEffect>& effects);
/// The effects of `effects` that are of the log (gain@joint), for ModelSnapshot::measurement.
std::vector<ModelEffect> MeasurementEffects(const std::vector<ModelEffect>& effects);

/// The values at RobotDynamics parameters x.
ModelSnapshot SnapshotAt(const RobotDynamics& model, const Eigen::VectorXd& x);

/// The online estimator's current values. For linear RLS (pi itself, no consistency by
/// construction): each tree body's pi, payloads merged into their links.
/// @throws std::invalid_argument naming the body or effect when the estimate is not a physical
/// model (a body that is not fully physically consistent, a negative non-negative coefficient).
ModelSnapshot SnapshotOf(const OnlineJointEstimator& estimator);

/// The model's effects with their values, as a model file states them.
std::vector<ModelEffect> EffectsOf(const RobotDynamics& model, const ModelSnapshot& snapshot);

/// Writes the robot's URDF (read from urdf_path, the file `robot` was loaded from) to out_path with
/// the snapshot's bodies and effects; `origin` says where the values come from (top comment).
/// @throws UrdfError as WriteUrdfModel; std::invalid_argument if the snapshot does not fit the model.
void WriteModelUrdf(const std::string& urdf_path, const std::string& out_path, const RobotModel& robot,
                    const RobotDynamics& model, const ModelSnapshot& snapshot, const std::string& origin);

/// The effect specs of a model: the file's declared effects (urdf_model.hpp), then `extra` (e.g.
/// from --effects); an extra effect of the same kind and target replaces the file's, one without a
/// target (every joint) replaces the file's of that kind on every joint.
std::vector<EffectSpec> MergeEffects(const std::vector<EffectSpec>& from_file, const std::vector<EffectSpec>& extra);

/// The identification model of a URDF robot: its links (priors from <inertial>), the effects, gravity.
/// @throws std::invalid_argument naming a bad effect (unknown joint or link ...).
RobotDynamics MakeRobotDynamics(const RobotModel& robot, const std::vector<EffectSpec>& effects,
                                const Vector3& gravity = Vector3(0, 0, -9.81));

}  // namespace inertial
