/// @file kdl_tree.hpp
/// Orocos KDL's tree inverse dynamics on a URDF, an implementation the project did not write, for
/// the tests that check ours against it: the URDF is converted to a KDL::Tree straight from
/// urdfdom's model (no kdl_parser, and nothing of the code under test). Test programs whose name
/// starts with kdl_ link KDL (tests/CMakeLists.txt).
#pragma once

#include <urdf_parser/urdf_parser.h>

#include <Eigen/Core>
#include <kdl/frames.hpp>
#include <kdl/jntarray.hpp>
#include <kdl/tree.hpp>
#include <kdl/treeidsolver_recursive_newton_euler.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "inertial/formats/urdf_model.hpp"

namespace inertial::testing {

// --- urdfdom model -> KDL::Tree ---

inline KDL::Frame KdlFrame(const urdf::Pose& pose) {
  return KDL::Frame(KDL::Rotation::Quaternion(pose.rotation.x, pose.rotation.y, pose.rotation.z, pose.rotation.w),
                    KDL::Vector(pose.position.x, pose.position.y, pose.position.z));
}

// KDL's inertia of a segment is about and in the segment's (tip = child link) frame. URDF gives the
// tensor about the COM in the COM frame's axes: build it there (RigidBodyInertia(m, 0, I_C)) and let
// KDL move it to the link frame.
inline KDL::RigidBodyInertia KdlInertia(const urdf::InertialSharedPtr& inertial) {
  if (!inertial) return KDL::RigidBodyInertia::Zero();
  const KDL::RotationalInertia I_C(inertial->ixx, inertial->iyy, inertial->izz, inertial->ixy, inertial->ixz,
                                   inertial->iyz);
  return KdlFrame(inertial->origin) * KDL::RigidBodyInertia(inertial->mass, KDL::Vector::Zero(), I_C);
}

inline KDL::Joint KdlJoint(const urdf::Joint& joint) {
  const KDL::Frame F = KdlFrame(joint.parent_to_joint_origin_transform);
  KDL::Vector axis(joint.axis.x, joint.axis.y, joint.axis.z);
  switch (joint.type) {
    case urdf::Joint::REVOLUTE:
    case urdf::Joint::CONTINUOUS:
      axis.Normalize();
      return KDL::Joint(joint.name, F.p, F.M * axis, KDL::Joint::RotAxis);
    case urdf::Joint::PRISMATIC:
      axis.Normalize();
      return KDL::Joint(joint.name, F.p, F.M * axis, KDL::Joint::TransAxis);
    case urdf::Joint::FIXED:
      return KDL::Joint(joint.name, KDL::Joint::Fixed);
    default:
      throw std::runtime_error("test: joint type not handled: " + joint.name);
  }
}

inline void AddChildren(const urdf::Link& link, KDL::Tree* tree) {
  for (const urdf::LinkSharedPtr& child : link.child_links) {
    const urdf::Joint& joint = *child->parent_joint;
    const KDL::Segment segment(child->name, KdlJoint(joint), KdlFrame(joint.parent_to_joint_origin_transform),
                               KdlInertia(child->inertial));
    if (!tree->addSegment(segment, link.name)) throw std::runtime_error("test: KDL refused segment " + child->name);
    AddChildren(*child, tree);
  }
}

inline KDL::Tree KdlTreeFromUrdf(const std::string& xml) {
  const urdf::ModelInterfaceSharedPtr model = urdf::parseURDF(xml);
  if (!model) throw std::runtime_error("test: urdfdom could not parse the URDF");
  KDL::Tree tree(model->getRoot()->name);
  AddChildren(*model->getRoot(), &tree);
  return tree;
}

// KDL inverse dynamics in the model's DOF order (KDL numbers joints by q_nr: matched by joint name).
class KdlInverseDynamics {
 public:
  KdlInverseDynamics(const std::string& xml, const RobotModel& model)
      : tree_(KdlTreeFromUrdf(xml)), kdl_index_(model.tree.num_dofs(), -1) {
    for (const auto& [name, element] : tree_.getSegments()) {
      const KDL::Joint& joint = GetTreeElementSegment(element).getJoint();
      if (joint.getType() == KDL::Joint::Fixed) continue;
      const int dof = model.DofIndex(joint.getName());
      if (dof < 0) throw std::runtime_error("test: KDL joint " + joint.getName() + " is not a DOF of the model");
      kdl_index_[dof] = static_cast<int>(GetTreeElementQNr(element));
      zero_wrenches_[name] = KDL::Wrench::Zero();
    }
    for (const int k : kdl_index_) {
      if (k < 0) throw std::runtime_error("test: a DOF of the model is not in the KDL tree");
    }
  }

  Eigen::VectorXd operator()(const Eigen::VectorXd& q, const Eigen::VectorXd& qd, const Eigen::VectorXd& qdd,
                             const Vector3& g) const {
    const int n = static_cast<int>(kdl_index_.size());
    KDL::JntArray kq(n), kqd(n), kqdd(n), ktau(n);
    for (int i = 0; i < n; ++i) {
      kq(kdl_index_[i]) = q[i];
      kqd(kdl_index_[i]) = qd[i];
      kqdd(kdl_index_[i]) = qdd[i];
    }
    KDL::TreeIdSolver_RNE solver(tree_, KDL::Vector(g.x(), g.y(), g.z()));
    if (solver.CartToJnt(kq, kqd, kqdd, zero_wrenches_, ktau) < 0) throw std::runtime_error("test: KDL solver failed");
    Eigen::VectorXd tau(n);
    for (int i = 0; i < n; ++i) tau[i] = ktau(kdl_index_[i]);
    return tau;
  }

  unsigned num_joints() const { return tree_.getNrOfJoints(); }

 private:
  KDL::Tree tree_;
  std::vector<int> kdl_index_;  // KDL's q_nr of each of the model's DOFs
  KDL::WrenchMap zero_wrenches_;
};

}  // namespace inertial::testing
