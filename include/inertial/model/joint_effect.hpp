/// @file joint_effect.hpp
/// The catalog of effects beyond the links' rigid-body dynamics, and the `--effects` syntax.
///
/// Joint effects (torque on joint j; every coefficient that must be non-negative is c = e^s with s
/// free, as the paper does for friction in eq. 14):
///   viscous   b qd                      b >= 0          [N m s/rad]
///   coulomb   bc tanh(qd / v_s)         bc >= 0         [N m]; smoothed sign(qd), v_s = `scale`
///                                                       (default 0.01 rad/s; tanh is within 2 % of
///                                                       sign(qd) for |qd| > 2.3 v_s)
///   asymmetric  bp s+ + bn s-           bp, bn >= 0     [N m]; Coulomb friction with its own level in
///                                                       each direction: s = tanh(qd / v_s), s+ = max(s, 0),
///                                                       s- = min(s, 0) (v_s = `scale`, as coulomb)
///   sigmoid   p1 (S(p2 (qd + p3)) - S(p2 p3))           [N m]; the friction model of Gaz et al.,
///                                       p1 >= 0         "Dynamic identification of the Franka Emika Panda
///                                                       robot with retrieval of feasible parameters using
///                                                       penalty-based optimization", RA-L 4(4) 2019, eq. 8:
///                                                       S(x) = 1 / (1 + e^-x), steepness p2 = `steepness`
///                                                       [s/rad] (default 50), shift p3 = `shift` [rad/s]
///                                                       (default 0, may be negative); zero at qd = 0,
///                                                       levels p1 (1 - S(p2 p3)) and -p1 S(p2 p3)
///   offset    c                         free            [N m] (torque-sensor bias)
///   armature  Ia qdd                    Ia >= 0         [kg m^2] (reflected rotor inertia)
///   spring    k (q - q0)                k >= 0, q0 free [N m/rad], [rad]
/// A measurement effect (not a torque: how the log's torque column relates to the joint torque):
///   gain      the logged quantity is g tau (a motor current with an unknown torque constant and
///             gear), g > 0 [log unit per N m]; fitted by gain_identification.hpp, not part of the
///             dynamics' coefficients (RobotDynamics has no term for it).
/// Body effects (ten log-Cholesky parameters each, relative to a prior body, eq. 11):
///   payload   an extra rigid body fixed to a link (default prior: a 0.5 kg sphere of radius 0.05 m
///             at the link origin; `mass=`, `radius=` change it)
///   rotor     a motor rotor behind a gearbox of ratio `gear` (required), on the joint's parent
///             link, coaxial with the joint, turning at gear * qd (default prior: a 0.3 kg cylinder of
///             radius 0.04 m and length 0.03 m; `mass=`, `radius=`, `length=` change it).
/// (Units are those of revolute joints; prismatic joints use N, m, kg.)
///
/// The velocity scale of coulomb and asymmetric and the steepness and shift of sigmoid are fixed per
/// term (the coefficients stay linear in the features); `inertial diagnose` fits them to the data
/// when it offers these effects (joint_diagnosis.hpp).
/// Syntax of a list: items separated by commas, each `kind[@target][:key=value...]`, e.g.
///   viscous,coulomb@knee:scale=0.05,sigmoid@elbow:steepness=40:shift=0.02,payload@tool0:mass=2,rotor@hip:gear=6
/// A joint effect without a target applies to every actuated joint; payload and rotor need one.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "inertial/inertia/inertial_params.hpp"

namespace inertial {

enum class EffectKind { kViscous, kCoulomb, kOffset, kArmature, kSpring, kPayload, kRotor, kAsymmetric, kSigmoid, kGain };

/// "viscous", "coulomb", "offset", "armature", "spring", "payload", "rotor", "asymmetric", "sigmoid", "gain".
std::string_view ToString(EffectKind kind);
/// Every kind, in the order of EffectKind.
const std::vector<EffectKind>& AllEffectKinds();
/// True for the per-joint scalar effects (not payload or rotor; gain included).
bool IsJointEffect(EffectKind kind);
/// True for effects of the measurement rather than of the dynamics (gain).
bool IsMeasurementEffect(EffectKind kind);

struct EffectSpec {
  EffectKind kind = EffectKind::kViscous;
  std::string target;            ///< joint (joint effects, rotor) or link (payload); empty: every joint
  double velocity_scale = 0.01;  ///< coulomb, asymmetric smoothing v_s [rad/s or m/s]
  double steepness = 50.0;       ///< sigmoid p2 [s/rad or s/m]
  double shift = 0.0;            ///< sigmoid p3 [rad/s or m/s]
  double gear_ratio = 0.0;       ///< rotor: rotor rate / joint rate (required, non-zero)
  double mass = 0.0;             ///< payload / rotor prior mass [kg] (0: the default above)
  double radius = 0.0;           ///< payload / rotor prior radius [m] (0: the default above)
  double length = 0.0;           ///< rotor prior length [m] (0: the default above)
  std::string text;              ///< the item as written, for messages
  /// Payload / rotor: the prior body itself, replacing the default shape above (a payload in its
  /// link's frame; a rotor in its own frame: origin on the joint axis where the joint frame is,
  /// axes those of the joint frame at rotor angle 0). Set when a model file states the body.
  std::optional<InertialParams> inertia;
  /// Payload: its 10 regressor columns form a block of their own (RobotDynamics::EstimatedBody::
  /// block) instead of adding to its link's, so that a fit of several runs can give them only to
  /// the run that carried it (estimation/batch/run_local_bodies.hpp).
  bool own_features = false;
};

/// An effect with known coefficients, as a model file holds it (urdf_effects.hpp).
struct ModelEffect {
  EffectSpec spec;  ///< a joint effect has one target joint; a body effect has spec.inertia set
  /// Joint effects: the physical coefficients in RobotDynamics::EffectValues order ({b}, {bc},
  /// {c}, {Ia}, {k, q0}, {bp, bn}, {p1}, {g}); body effects: empty.
  std::vector<double> values;
};

/// The number of coefficients of a joint effect of `kind` (2 for spring and asymmetric, else 1; 0 for
/// bodies).
int NumEffectValues(EffectKind kind);

/// The names of those coefficients, in that order: {"b"}, {"bc"}, {"c"}, {"Ia"}, {"k", "q0"},
/// {"bp", "bn"}, {"p1"}, {"g"}; empty for bodies.
std::vector<std::string> EffectValueNames(EffectKind kind);

/// The sigmoid friction feature at unit amplitude: S(p2 (qd + p3)) - S(p2 p3), S(x) = 1 / (1 + e^-x).
double SigmoidFriction(double qd, double steepness, double shift);

/// The torque of a velocity-only joint effect (viscous, coulomb, asymmetric, sigmoid, offset) with
/// coefficients `values` (ModelEffect order) at joint velocity qd; NaN for the other kinds.
double VelocityEffectTorque(const EffectSpec& spec, const std::vector<double>& values, double qd);

/// The item in `--effects` syntax that gives back `spec` (kind@target with the shape options of
/// coulomb, asymmetric and sigmoid, a rotor's gear, the prior's mass, radius and length where set;
/// 4 significant digits), e.g. "coulomb@knee:scale=0.0125". A body stated by a model file
/// (spec.inertia) is not an item: its prior shape comes out as the default one.
std::string EffectItem(const EffectSpec& spec);

/// Parses a comma-separated list. Targets are not checked against a model here.
/// @throws std::invalid_argument naming the item and what is wrong (unknown kind, missing target,
/// unknown key, bad number, missing gear ratio).
std::vector<EffectSpec> ParseEffectList(std::string_view text);

}  // namespace inertial
