/// @file kinematic_tree.hpp
/// A fixed-base kinematic tree of rigid bodies connected by 1-DOF joints (revolute or prismatic) or
/// fixed joints, with the joint-space inverse dynamics (recursive Newton-Euler, Featherstone 2008,
/// Table 5.1) and the joint-torque regressor tau = Y(q, qd, qdd) pi_all, linear in every body's pi.
///
/// Frames: each body's frame is its joint's frame after the joint motion (URDF convention: the
/// joint frame sits at `origin` in the parent body's frame and the child link frame coincides with
/// it). A revolute joint rotates about `axis` (unit, in the joint frame) by q [rad]; a prismatic
/// joint translates along it by q [m]. Bodies must be added parents first.
/// Conventions: pi of each body about its own frame origin, in its own frame (types.hpp order);
/// spatial vectors angular first; gravity g expressed in the base frame (default -9.81 along z).
#pragma once

#include <string>
#include <vector>

#include "inertial/inertia/inertial_params.hpp"

namespace inertial {

enum class JointType { kRevolute, kPrismatic, kFixed };

struct JointModel {
  std::string name;
  JointType type = JointType::kRevolute;
  Matrix3 R_parent_joint = Matrix3::Identity();  ///< joint frame orientation in the parent frame
  Vector3 p_parent_joint = Vector3::Zero();      ///< joint frame origin in the parent frame [m]
  Vector3 axis = Vector3::UnitZ();               ///< unit axis in the joint frame
};

/// A spatial motion transform from frame A to frame B coordinates, stored as R_AB (B's axes in A)
/// and p_AB (B's origin in A). Motion: X v = [R^T w; R^T (v - p x w)]; force transpose: X^T f.
struct SpatialTransform {
  Matrix3 R_AB = Matrix3::Identity();
  Vector3 p_AB = Vector3::Zero();
  Vector6 ApplyToMotion(const Vector6& v_A) const;     ///< A -> B coordinates
  Vector6 ApplyTransposeToForce(const Vector6& f_B) const;  ///< B -> A coordinates (X^T f)
};

/// Scratch memory of the tree's recursions (transforms, velocities, accelerations of every body),
/// sized once by KinematicTree::MakeWorkspace so that the allocation-free overloads never allocate.
struct TreeWorkspace {
  std::vector<SpatialTransform> X;
  std::vector<Vector6> v, a;
};

class KinematicTree {
 public:
  /// Adds a body with parent index `parent` (-1: the fixed base) and returns its index.
  /// @throws std::invalid_argument if the parent does not exist yet, the axis is not a unit vector
  /// (within 1e-9) or any number is not finite.
  int AddBody(const std::string& name, int parent, const JointModel& joint, const InertialParams& inertia);

  /// Adds a geared rotor: a body on `parent` that turns about its own revolute `joint` at
  /// gear_ratio * qd[driven_dof] (a motor rotor behind a gearbox, as in the Cheetah leg of the
  /// paper's Section VII). It adds no DOF; its reaction appears on driven_dof multiplied by the
  /// ratio and on the parent chain. Returns its body index.
  /// @throws std::invalid_argument as AddBody, and if the joint is not revolute, driven_dof does
  /// not exist or the ratio is zero or not finite.
  int AddRotor(const std::string& name, int parent, const JointModel& joint, const InertialParams& inertia,
               int driven_dof, double gear_ratio);

  int num_bodies() const { return static_cast<int>(bodies_.size()); }
  /// Number of 1-DOF joints (fixed joints have none). q, qd, qdd, tau have this size.
  int num_dofs() const { return num_dofs_; }
  const std::string& body_name(int i) const { return bodies_[i].name; }
  const JointModel& joint(int i) const { return bodies_[i].joint; }
  int parent(int i) const { return bodies_[i].parent; }
  /// The DOF index of body i's joint (for a rotor: the DOF that drives it), or -1 for a fixed joint.
  int dof_index(int i) const { return bodies_[i].dof; }
  /// Joint rate of body i per unit rate of its DOF: 1 for joints, the gear ratio for rotors.
  double gear_ratio(int i) const { return bodies_[i].gear; }
  bool is_rotor(int i) const { return bodies_[i].rotor; }
  const InertialParams& inertia(int i) const { return bodies_[i].inertia; }
  /// All bodies' pi stacked (10 per body, in body order).
  Eigen::VectorXd StackedParameters() const;

  /// Transform from the parent frame to body i's frame at joint position q_i.
  SpatialTransform ParentToBody(int i, double q_i) const;

  /// Joint torques/forces by recursive Newton-Euler. Sizes must be num_dofs().
  Eigen::VectorXd InverseDynamics(const Eigen::VectorXd& q, const Eigen::VectorXd& qd, const Eigen::VectorXd& qdd,
                                  const Vector3& g_base = Vector3(0, 0, -9.81)) const;
  /// The same with every body's pi taken from `pi` (10 per body, in body order, as
  /// StackedParameters()) instead of the tree's own: Y(q, qd, qdd) pi in O(bodies) instead of the
  /// regressor's O(bodies x depth x 10). pi need not be physically consistent (the map is linear).
  /// @throws std::invalid_argument on wrong sizes.
  Eigen::VectorXd InverseDynamics(const Eigen::VectorXd& pi, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                                  const Eigen::VectorXd& qdd, const Vector3& g_base) const;

  /// Y (num_dofs x 10 num_bodies) with tau = Y StackedParameters(). O(bodies x depth).
  Eigen::MatrixXd JointTorqueRegressor(const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                                       const Eigen::VectorXd& qdd, const Vector3& g_base = Vector3(0, 0, -9.81)) const;

  /// A workspace for the overload below (allocates; call once, outside any real-time loop).
  TreeWorkspace MakeWorkspace() const;

  /// The same Y into `Y` (num_dofs x 10 num_bodies), allocation-free and without exceptions, for
  /// per-sample use. Preconditions (debug-asserted, the caller checks them): q, qd, qdd have
  /// num_dofs() entries, `workspace` comes from MakeWorkspace() of this tree, Y has the right size.
  void JointTorqueRegressor(const Eigen::VectorXd& q, const Eigen::VectorXd& qd, const Eigen::VectorXd& qdd,
                            const Vector3& g_base, TreeWorkspace* workspace, Eigen::Ref<Eigen::MatrixXd> Y) const;

  /// Body twists (in body frames) at (q, qd): for tests and energy computations.
  std::vector<Vector6> BodyVelocities(const Eigen::VectorXd& q, const Eigen::VectorXd& qd) const;
  /// Pose of every body in the base frame (R_base_body, p_base_body).
  std::vector<SpatialTransform> BodyPoses(const Eigen::VectorXd& q) const;

 private:
  struct Body {
    std::string name;
    int parent = -1;
    int dof = -1;
    double gear = 1.0;
    bool rotor = false;
    JointModel joint;
    InertialParams inertia;
  };
  // Velocities and accelerations of every body (a includes -g at the base: gravity as acceleration).
  // Sizes checked by the caller; writes every entry of the (already sized) workspace vectors.
  void Kinematics(const Eigen::VectorXd& q, const Eigen::VectorXd& qd, const Eigen::VectorXd& qdd,
                  const Vector3& g_base, TreeWorkspace* ws) const;
  void CheckSizes(const Eigen::VectorXd& q, const Eigen::VectorXd& qd, const Eigen::VectorXd& qdd) const;
  Vector6 MotionSubspace(int i) const;
  std::vector<Body> bodies_;
  int num_dofs_ = 0;
};

}  // namespace inertial
