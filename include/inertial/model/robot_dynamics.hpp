/// @file robot_dynamics.hpp
/// A robot's joint-space dynamics with every unknown in one parameter vector x:
///
///   tau = A(q, qd, qdd) w(x),
///
/// where A = [Y  Phi] holds the joint-torque regressor Y of every tree body (links and rotors, 10
/// columns each) and the effect features Phi (qd, tanh(qd/v_s), 1, qdd, q, the sigmoid ...), and w(x) stacks the
/// bodies' pi and the effect coefficients. A depends on the data only; w on the parameters only.
///
/// x = [theta of every estimated body (10 each, log-Cholesky relative to its prior, eq. 11: x = 0
/// is the prior); effect parameters]. Estimated bodies are, in order: every tree body (URDF links,
/// then rotors), then payloads (each adds to the pi block of the tree body its link belongs to, or
/// has a block of its own: EffectSpec::own_features).
/// Effect parameters: s with coefficient e^s for viscous, coulomb, armature, sigmoid (non-negative
/// by construction); [s+, s-] for asymmetric (bp = e^s+, bn = e^s-); c for offset; [s, q0] for
/// spring (k = e^s, features q and -1 with coefficients k and k q0). See joint_effect.hpp for the
/// catalog.
/// Conventions: pi about each tree body's frame origin in its axes (types.hpp order); SI units;
/// gravity in the base frame.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "inertial/inertia/log_cholesky.hpp"
#include "inertial/model/body_region.hpp"
#include "inertial/model/joint_effect.hpp"
#include "inertial/model/kinematic_tree.hpp"

namespace inertial {

/// Where a link sits: its tree body and the link frame's pose in that body's frame.
struct LinkLocation {
  int body = -1;
  SpatialTransform link_in_body;
};
/// Finds a link by name (links merged by fixed joints included); false if there is none.
using LinkResolver = std::function<bool(const std::string& link, LinkLocation* location)>;

struct EstimatedBody {
  std::string name;          ///< link name, "rotor@<joint>" or "payload@<link>"
  int tree_body = -1;        ///< the tree body whose motion it shares
  /// Its 10 columns of A and entries of w start at 10 block: tree_body, except for a payload
  /// with EffectSpec::own_features, whose block (after every tree body's) repeats its tree body's
  /// columns so that a fit can give them to some samples only (a run that carried it).
  int block = -1;
  InertialParams prior;      ///< in the tree body's frame
  LogCholeskyParameterization map;  ///< relative to the prior (eq. 11)
  SpatialTransform report_frame;    ///< the user's frame for it, posed in the tree body's frame
  /// Where its mass may lie (body_region.hpp), in the tree body's frame; none for rotors. Every fit
  /// keeps the body inside (joint_identification.hpp's barrier).
  std::optional<BodyRegion> region;
};

struct EffectTerm {
  EffectKind kind = EffectKind::kViscous;
  int dof = -1;
  std::string joint;
  double velocity_scale = 0.01;  ///< coulomb, asymmetric
  double steepness = 50.0;       ///< sigmoid
  double shift = 0.0;            ///< sigmoid
  int first_parameter = 0;       ///< index into x
  int first_feature = 0;         ///< index into w and the columns of A
  int size() const { return NumEffectValues(kind); }
};

class RobotDynamics {
 public:
  /// @param links the robot's links (no rotors); @param dof_names the joint name of every DOF.
  /// @throws std::invalid_argument naming the effect and what is wrong: unknown joint or link,
  /// an effect given twice for a joint, a payload on the fixed base.
  RobotDynamics(const KinematicTree& links, std::vector<std::string> dof_names, const std::vector<EffectSpec>& effects,
                const LinkResolver& resolve_link, const Vector3& gravity = Vector3(0, 0, -9.81));

  int num_dofs() const { return tree_.num_dofs(); }
  int num_parameters() const { return num_parameters_; }
  int num_features() const { return num_features_; }
  /// The bodies' columns of A: every tree body's block, then the own blocks of payloads with
  /// EffectSpec::own_features (none in most models); the effect features follow.
  int num_inertia_features() const { return 10 * num_blocks_; }
  int num_tree_features() const { return 10 * tree_.num_bodies(); }
  const KinematicTree& tree() const { return tree_; }  ///< links and rotors
  const std::vector<std::string>& dof_names() const { return dof_names_; }
  const std::vector<EstimatedBody>& bodies() const { return bodies_; }
  const std::vector<EffectTerm>& effects() const { return effects_; }
  const Vector3& gravity() const { return gravity_; }

  /// Names of the entries of x ("thigh.alpha", "viscous@knee.log_b", ...) and of w / the columns
  /// of A ("thigh.m", "thigh.hx", ..., "viscous@knee.b").
  std::vector<std::string> ParameterNames() const;
  std::vector<std::string> FeatureNames() const;

  /// A(q, qd, qdd) into rows [0, num_dofs) of `A` (num_dofs x num_features).
  void Features(const Eigen::VectorXd& q, const Eigen::VectorXd& qd, const Eigen::VectorXd& qdd,
                Eigen::Ref<Eigen::MatrixXd> A) const;
  /// Allocation-free, exception-free form for per-sample use, with a workspace from
  /// MakeWorkspace(). Preconditions (debug-asserted): sizes as above.
  void Features(const Eigen::VectorXd& q, const Eigen::VectorXd& qd, const Eigen::VectorXd& qdd,
                TreeWorkspace* workspace, Eigen::Ref<Eigen::MatrixXd> A) const;
  TreeWorkspace MakeWorkspace() const { return tree_.MakeWorkspace(); }
  /// w(x) and (optionally) J_w_x (num_features x num_parameters, block diagonal per body/effect).
  Eigen::VectorXd Coefficients(const Eigen::VectorXd& x, Eigen::MatrixXd* J_w_x = nullptr) const;
  /// tau = A(q, qd, qdd) w(x), by recursive Newton-Euler on the bodies of w plus the effect terms
  /// (O(bodies), not the regressor's O(bodies x depth x 10)).
  Eigen::VectorXd InverseDynamics(const Eigen::VectorXd& x, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                                  const Eigen::VectorXd& qdd) const;
  /// The same from coefficients w = Coefficients(x) computed once: what a simulator calls at every
  /// step. @throws std::invalid_argument on wrong sizes.
  Eigen::VectorXd InverseDynamicsFromCoefficients(const Eigen::VectorXd& w, const Eigen::VectorXd& q,
                                                  const Eigen::VectorXd& qd, const Eigen::VectorXd& qdd) const;

  /// x from effect coefficients w_e (one value per effect feature, as in w): theta = 0 for every
  /// body; non-negative coefficients floored at `floor` before the log; spring q0 = (k q0) / k.
  Eigen::VectorXd ParametersFromEffectCoefficients(const Eigen::VectorXd& effect_coefficients,
                                                   double floor = 1e-6) const;
  /// x of a model whose coefficients are known: theta = 0 for every body (a file's payloads and
  /// rotors are priors set to their stated inertia, EffectSpec::inertia) and each effect term's
  /// parameters from the ModelEffect of the same kind on its joint (a zero non-negative
  /// coefficient becomes e^s = 1e-300). @throws std::invalid_argument naming a term that has no
  /// values, values of the wrong count, or a negative or non-finite coefficient.
  Eigen::VectorXd ParametersFromEffectValues(const std::vector<ModelEffect>& effects) const;
  /// Replaces estimated body e's region (body_region.hpp; nullopt: none, the body is then only
  /// physically consistent). @throws std::invalid_argument if e is not a body, or the region does not
  /// hold the body's prior strictly (slack > 0, mass below max_mass): a fit starts at the prior.
  void SetBodyRegion(int e, std::optional<BodyRegion> region);
  /// Estimated body e at x, in its report frame.
  InertialParams BodyInertia(int e, const Eigen::VectorXd& x) const;
  /// The physical coefficients of effect term k at x: {b}, {bc}, {c}, {Ia}, {k, q0}, {bp, bn} or {p1}.
  std::vector<double> EffectValues(int k, const Eigen::VectorXd& x) const;

 private:
  void AssignDefaultRegions();  // body_region.hpp's sources 2-4 (formats/ adds source 1)

  KinematicTree tree_;
  std::vector<std::string> dof_names_;
  std::vector<EstimatedBody> bodies_;
  std::vector<EffectTerm> effects_;
  Vector3 gravity_;
  int num_parameters_ = 0;
  int num_features_ = 0;
  int num_blocks_ = 0;
};

}  // namespace inertial
