/// @file urdf_model.hpp
/// Loading a URDF robot description (parsed by urdfdom) into a fixed-base KinematicTree.
///
/// What is read:
/// - Joints `revolute` and `continuous` (both revolute), `prismatic` and `fixed`, with their
///   `<origin xyz rpy>` (rpy fixed-axis roll-pitch-yaw: R = Rz(yaw) Ry(pitch) Rx(roll)) and `<axis>`
///   (any non-zero direction, normalized; URDF's default (1, 0, 0) when absent). Several branches (any
///   tree) are fine. Collision primitives (box, cylinder, sphere) bound each link's region
///   (body_region.hpp); visuals, meshes and safety controllers are not used.
/// - `<limit lower upper velocity effort>` of the moving joints (RobotModel::dof_limits, what
///   `simulate` keeps to): an absent attribute, and a velocity or effort of 0 (what exporters
///   write for "unknown"), states no limit; a continuous joint's lower and upper are ignored.
///   Unlike urdfdom (which reads an absent lower or upper as 0) nothing is invented.
/// - `<inertial>`: mass, `<origin>` of the COM frame C in the link frame L and the inertia tensor
///   about the COM in C's axes (ixx .. izz are the tensor entries as written, ixy being the (0,1)
///   entry). It is converted exactly to pi about L's origin in L's axes: I_L = R_LC I_C R_LC^T, then
///   the parallel-axis theorem.
/// - The root link is the fixed base; its own inertia never matters. Each link reached through a
///   moving joint starts a tree body; links attached by fixed joints are merged into the body they
///   hang from (their inertias transformed and added exactly). Links fixed to the root belong to the
///   base (BodyIndex -1) and their inertias are ignored.
/// - Bodies and DOFs follow the file order of the joints (parents always before children).
///
/// Like urdfdom, a joint with several `<origin>` elements uses the first one. urdfdom keeps a link
/// whose `<inertial>` it cannot parse (missing mass or inertia) and only logs an error; here every
/// error urdfdom logs makes the file invalid.
///
/// Consistency (UrdfLoadOptions::require_consistent_inertials, default on): every `<inertial>` of a
/// link of a moving body must be fully physically consistent (CheckConsistency), except an all-zero
/// one (mass 0 and inertia 0: a massless marker link); every moving body must get mass from at least
/// one of its links. With the option off, any numbers are accepted and a body without `<inertial>`
/// gets the zero inertia.
///
/// Effects (the model file). A URDF can state the model's effects with their coefficients:
/// - standard `<dynamics damping="b" friction="bc"/>` of a moving joint: viscous b qd and Coulomb
///   bc tanh(qd / v_s) (v_s = 0.01 rad/s unless stated below); zero values are no effect;
/// - one extension element, a child of <robot> that other URDF readers ignore:
///     <inertial_effects version="1">
///       <viscous joint="J"/>                               (b: J's <dynamics damping>)
///       <coulomb joint="J" velocity_scale="v_s"/>          (bc: J's <dynamics friction>)
///       <offset joint="J" torque="c"/>                     [N m]
///       <armature joint="J" inertia="Ia"/>                 [kg m^2]
///       <spring joint="J" stiffness="k" rest_position="q0"/>
///       <asymmetric joint="J" velocity_scale="v_s" positive="bp" negative="bn"/>   [N m]
///       <sigmoid joint="J" amplitude="p1" steepness="p2" shift="p3"/>               [N m, s/rad, rad/s]
///       <rotor joint="J" gear_ratio="N"><inertial>...</inertial></rotor>
///       <payload link="L"><inertial>...</inertial></payload>
///       <gain joint="J" value="g"/>    (J's torque column is g tau: e.g. a motor current [A per N m])
///     </inertial_effects>
///   A rotor's <inertial> is in the rotor's frame (the joint frame at rotor angle 0: origin and axes
///   of the child link's frame at q = 0), a payload's in its link's frame; both as URDF <inertial>.
/// RobotModel::effects holds all of them (what `inertial validate` evaluates); the ones the extension
/// states are RobotModel::DeclaredEffects() (what the fitting commands add to their model: bare
/// <dynamics> values of other tools' URDFs are often simulator settings, so they are not fitted
/// unless asked for with --effects). Every number is parsed strictly (a finite decimal).
///
/// Priors (the model file). A model file written by inertial records, in a second extension
/// element, each link's inertia in the URDF it was identified from (the fit's prior), in the link's
/// frame, so that the file's values can be judged against the drawing (validate, check:
/// formats/model_plausibility.hpp):
///     <inertial_priors version="1">
///       <prior link="L"><inertial>...</inertial></prior>        (L: a link that starts a moving body)
///     </inertial_priors>
/// RobotModel::recorded_priors holds them; nothing else uses them (a fit from a model file starts
/// from the file's own inertias). Read strictly, like <inertial_effects>.
///
/// Limits (refused before urdfdom sees the file), each bounding a cost that grows faster than the
/// file: a file over kMaxUrdfBytes (input_file.hpp); a tag with more than kMaxUrdfAttributes
/// attributes (checked before any XML parser runs: tinyxml2 and urdfdom look for a duplicate
/// attribute linearly, so 60,000 attributes on one tag took 8 s in tinyxml2 and 19 s in all); nesting
/// deeper than 100 elements (tinyxml2's limit); more than kMaxUrdfLinks links or joints; a position,
/// a shape size (origin xyz, box, cylinder, sphere, capsule) or a joint limit beyond kMaxUrdfLength.
///
/// Errors (UrdfError) start with the file path (or the source name given to ParseUrdf), e.g.
/// "robot.urdf: link 'thigh': <inertial> is not physically consistent: triangle inequality ...".
/// Not supported (errors): floating and planar joints, joints with `<mimic>`.
/// Thread safety: loads may run concurrently; the urdfdom step is serialized (urdfdom reports its
/// errors through console_bridge's process-wide log handler, which is captured meanwhile).
/// Conventions: SI units, spatial vectors angular first, pi order of types.hpp.
#pragma once

#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "inertial/inertia/inertial_params.hpp"
#include "inertial/model/joint_effect.hpp"
#include "inertial/model/joint_limits.hpp"
#include "inertial/model/kinematic_tree.hpp"

namespace inertial {

/// The largest length a URDF may state [m], a position, a shape's size or a joint limit (also [rad]).
/// The largest machines described by URDFs (cranes, excavators, telescope mounts) have links of tens
/// of metres; 1000 m is beyond any robot, while a model written in millimetres (a 1.2 m link as
/// 1200) is caught. 1000 rad is 160 turns.
inline constexpr double kMaxUrdfLength = 1e3;
/// The most attributes a URDF tag may have: URDF's own elements have at most 6 (<inertia>), a
/// <robot> generated by xacro a few namespaces more.
inline constexpr int kMaxUrdfAttributes = 32;
/// The most <link> (and <joint>) elements a URDF may have. Robots described by URDFs (humanoids with
/// hands, dual-arm mobile manipulators) have 50-200 links; every command's cost grows with the links
/// (the identification model's dense matrices with their square), and placing a chain written
/// children first with its square.
inline constexpr int kMaxUrdfLinks = 2000;

/// A URDF that cannot be read, parsed or used. The message starts with the file path.
struct UrdfError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// One URDF link's `<inertial>` as written in the file (before merging).
struct UrdfLinkInertial {
  std::string link;
  bool present = false;  ///< the link has an <inertial> element
  InertialParams pi;     ///< about the link frame origin, in link axes (zero when absent)
};

/// Where a URDF link sits in the model: its body (-1: the base) and its frame in that body's frame
/// (for links of the base: in the root link's frame).
struct LinkPlacement {
  int body = -1;
  SpatialTransform X_body_link;  ///< R_AB, p_AB with A = body frame, B = link frame
};

struct RobotModel {
  std::string name;       ///< robot name
  std::string root_link;  ///< the fixed base
  /// One body per moving link (named after it, its joint named after the URDF joint); links
  /// attached by fixed joints are merged into their parent body.
  KinematicTree tree;
  std::vector<std::string> body_links;  ///< the URDF link name of each tree body
  std::vector<bool> body_has_inertial;  ///< some link merged into that body has an <inertial>
  /// Per tree body: points on the collision shapes of the links merged into it, in its frame
  /// (body_region.hpp): primitives, and meshes whose files are found (mesh_vertices.hpp); none for
  /// a body some of whose material is not drawn (a mesh not read, a link with mass and no collision
  /// shape). And how many of its meshes were not read.
  std::vector<std::vector<Vector3>> body_shape_points;
  std::vector<int> body_shape_meshes;
  /// "LINK: URI (not found)" or the reader's error, for every mesh that was not read.
  std::vector<std::string> unread_meshes;
  std::vector<std::string> dof_names;   ///< the joint name of each DOF, in the tree's DOF order
  std::vector<JointLimits> dof_limits;  ///< the <limit> of each DOF (infinite where none is stated)
  std::vector<UrdfLinkInertial> links;  ///< every link of the file, in file order
  std::map<std::string, LinkPlacement> placements;  ///< every link by name
  /// Every effect the file states, with its coefficients (see the file comment).
  std::vector<ModelEffect> effects;
  /// One flag per effect: stated in <inertial_effects> (not only as a <dynamics> value).
  std::vector<bool> effect_declared;
  /// The priors <inertial_priors> records (see the file comment): body link -> pi about its frame
  /// origin in its axes (= its body's frame). Empty for a URDF that is not a model file.
  std::map<std::string, InertialParams> recorded_priors;

  /// The specs of the effects <inertial_effects> states (payload and rotor inertias as priors).
  std::vector<EffectSpec> DeclaredEffects() const;

  /// The DOF of a moving joint, or -1 if `joint` is not a moving joint of the model.
  int DofIndex(const std::string& joint) const;
  /// The body a link belongs to (also for links merged by fixed joints), or -1 if none (the root,
  /// links fixed to it, unknown names).
  int BodyIndex(const std::string& link) const;
  /// Pose of a (possibly merged) link frame in its body's frame (for a link of the base: in the root
  /// link's frame), e.g. for a payload attached to `tool0`.
  /// @throws std::invalid_argument if the model has no such link.
  SpatialTransform LinkInBody(const std::string& link) const;
};

struct UrdfLoadOptions {
  bool require_consistent_inertials = true;
  /// Where relative mesh paths and `package://` URIs are looked for (ResolveMeshUri); LoadUrdf
  /// takes the URDF's own folder when this is empty. Empty in ParseUrdf: meshes are not read (text
  /// handed over has no folder; nothing is read from the working directory behind a caller's back).
  std::string mesh_directory;
};

/// Reads and loads the URDF file at `path`. @throws UrdfError (see the file comment).
RobotModel LoadUrdf(const std::string& path, const UrdfLoadOptions& options = {});

/// Loads URDF text; `source_name` starts every error message (a path, or e.g. "<string>").
/// @throws UrdfError (see the file comment).
RobotModel ParseUrdf(const std::string& xml, const std::string& source_name, const UrdfLoadOptions& options = {});

/// The text of the URDF file at `path` (at most kMaxUrdfBytes). @throws UrdfError if it cannot be
/// read or is larger.
std::string ReadUrdfFile(const std::string& path);

}  // namespace inertial
