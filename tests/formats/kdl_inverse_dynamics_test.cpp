// RobotModel (LoadUrdf / ParseUrdf + KinematicTree) against Orocos KDL's tree recursive Newton-Euler
// on the same URDF, converted to a KDL::Tree here straight from urdfdom's model (no kdl_parser, and
// nothing of the code under test): the bundled example robots, the KUKA LWR4+ of the shared data
// when present, and random branched URDFs with fixed and prismatic joints and random rpy and axes.
#include <gtest/gtest.h>
#include <urdf_parser/urdf_parser.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <kdl/frames.hpp>
#include <kdl/jntarray.hpp>
#include <kdl/tree.hpp>
#include <kdl/treeidsolver_recursive_newton_euler.hpp>
#include <memory>
#include <string>
#include <vector>

#include "inertial/formats/urdf_model.hpp"
#include "formats/urdf_text.hpp"
#include "test_support.hpp"

namespace inertial {
namespace {

using testing::InertialXml;
using testing::JointXml;
using testing::LinkXml;
using testing::RelativeError;
using testing::Rng;
using testing::RobotXml;

// --- urdfdom model -> KDL::Tree ---

KDL::Frame KdlFrame(const urdf::Pose& pose) {
  return KDL::Frame(KDL::Rotation::Quaternion(pose.rotation.x, pose.rotation.y, pose.rotation.z, pose.rotation.w),
                    KDL::Vector(pose.position.x, pose.position.y, pose.position.z));
}

// KDL's inertia of a segment is about and in the segment's (tip = child link) frame. URDF gives the
// tensor about the COM in the COM frame's axes: build it there (RigidBodyInertia(m, 0, I_C)) and let
// KDL move it to the link frame.
KDL::RigidBodyInertia KdlInertia(const urdf::InertialSharedPtr& inertial) {
  if (!inertial) return KDL::RigidBodyInertia::Zero();
  const KDL::RotationalInertia I_C(inertial->ixx, inertial->iyy, inertial->izz, inertial->ixy, inertial->ixz,
                                   inertial->iyz);
  return KdlFrame(inertial->origin) * KDL::RigidBodyInertia(inertial->mass, KDL::Vector::Zero(), I_C);
}

KDL::Joint KdlJoint(const urdf::Joint& joint) {
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

void AddChildren(const urdf::Link& link, KDL::Tree* tree) {
  for (const urdf::LinkSharedPtr& child : link.child_links) {
    const urdf::Joint& joint = *child->parent_joint;
    const KDL::Segment segment(child->name, KdlJoint(joint), KdlFrame(joint.parent_to_joint_origin_transform),
                               KdlInertia(child->inertial));
    if (!tree->addSegment(segment, link.name)) throw std::runtime_error("test: KDL refused segment " + child->name);
    AddChildren(*child, tree);
  }
}

KDL::Tree KdlTreeFromUrdf(const std::string& xml) {
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

// Both inverse dynamics and the regressor times the stacked parameters against KDL at seeded random
// states, gravity both the default and random.
void ExpectMatchesKdl(const std::string& xml, const std::string& name, unsigned seed, int states = 30) {
  const RobotModel model = ParseUrdf(xml, name);
  const KdlInverseDynamics kdl(xml, model);
  const int n = model.tree.num_dofs();
  ASSERT_EQ(kdl.num_joints(), static_cast<unsigned>(n)) << name;
  const Eigen::VectorXd pi = model.tree.StackedParameters();
  Rng rng(seed);
  for (int k = 0; k < states; ++k) {
    Eigen::VectorXd q(n), qd(n), qdd(n);
    for (int i = 0; i < n; ++i) {
      q[i] = rng.Uniform(-3, 3);
      qd[i] = rng.Uniform(-3, 3);
      qdd[i] = rng.Uniform(-10, 10);
    }
    const Vector3 g = k % 2 == 0 ? Vector3(0, 0, -9.81) : rng.UniformVector<3>(-10, 10);
    const Eigen::VectorXd expected = kdl(q, qd, qdd, g);
    EXPECT_LT(RelativeError(model.tree.InverseDynamics(q, qd, qdd, g), expected), 1e-9) << name << " state " << k;
    EXPECT_LT(RelativeError(model.tree.JointTorqueRegressor(q, qd, qdd, g) * pi, expected), 1e-9)
        << name << " state " << k;
  }
}

// A random tree of n_links links: each hangs from a random earlier link by a revolute, continuous,
// prismatic or fixed joint with random origin (xyz, rpy) and unnormalized axis; each moving link and
// about half the fixed ones have a random box inertial with offset and rotated COM frame.
std::string RandomTreeUrdf(unsigned seed, int n_links) {
  Rng rng(seed);
  const double pi = 3.141592653589793;
  std::string body = LinkXml("link0");
  for (int k = 1; k < n_links; ++k) {
    const int parent = std::min(k - 1, static_cast<int>(rng.Uniform(0, k)));
    const double u = rng.Uniform(0, 1);
    const std::string type = u < 0.3 ? "revolute" : u < 0.5 ? "continuous" : u < 0.7 ? "prismatic" : "fixed";
    const std::string name = "link" + std::to_string(k);
    Vector3 axis(rng.Normal(), rng.Normal(), rng.Normal());
    axis *= rng.Uniform(0.2, 3.0) / axis.norm();
    body += JointXml("joint" + std::to_string(k), type, "link" + std::to_string(parent), name,
                     rng.UniformVector<3>(-0.5, 0.5), rng.UniformVector<3>(-pi, pi), axis);
    if (type == "fixed" && rng.Uniform(0, 1) < 0.5) {
      body += LinkXml(name);
      continue;
    }
    const double m = rng.Uniform(0.2, 3.0);
    const Vector3 size = rng.UniformVector<3>(0.05, 0.5);
    Matrix3 D = Matrix3::Zero();
    D(0, 0) = m / 12 * (size.y() * size.y() + size.z() * size.z());
    D(1, 1) = m / 12 * (size.x() * size.x() + size.z() * size.z());
    D(2, 2) = m / 12 * (size.x() * size.x() + size.y() * size.y());
    body += LinkXml(name, InertialXml(m, rng.UniformVector<3>(-0.2, 0.2), rng.UniformVector<3>(-pi, pi), D));
  }
  return RobotXml("random" + std::to_string(seed), body);
}

std::string SourceDir() {
  const char* dir = std::getenv("INERTIAL_SOURCE_DIR");
  return dir == nullptr ? std::string() : std::string(dir);
}

TEST(KdlInverseDynamics, RandomBranchedTreesWithFixedAndPrismaticJoints) {
  for (unsigned seed = 1; seed <= 8; ++seed) {
    const std::string xml = RandomTreeUrdf(seed, 14);
    ExpectMatchesKdl(xml, "random tree " + std::to_string(seed), 100 + seed);
  }
}

TEST(KdlInverseDynamics, ProductsOfInertiaFollowUrdfsConvention) {
  // A single link with products of inertia written directly (no COM rotation).
  Matrix3 I;
  I << 0.05, -0.004, 0.003, -0.004, 0.06, 0.002, 0.003, 0.002, 0.07;
  const std::string xml = RobotXml("p", LinkXml("a") + LinkXml("b", InertialXml(1.5, Vector3(0.2, 0.1, -0.3), Vector3::Zero(), I)) +
                                            JointXml("j", "continuous", "a", "b", Vector3::Zero(), Vector3(0.4, 0.5, 0.6),
                                                     Vector3(1, 2, 3)) +
                                            LinkXml("c", InertialXml(1.0, Vector3(0.1, 0, 0), Vector3::Zero(), I)) +
                                            JointXml("k", "continuous", "b", "c", Vector3(0.3, 0, 0), Vector3::Zero(),
                                                     Vector3(0, 1, 0)));
  ExpectMatchesKdl(xml, "products", 7);
}

TEST(KdlInverseDynamics, ExampleLeg) {
  if (SourceDir().empty()) GTEST_SKIP() << "INERTIAL_SOURCE_DIR is not set (run through ctest)";
  ExpectMatchesKdl(testing::ReadTextFile(SourceDir() + "/examples/leg3.urdf"), "leg3.urdf", 41);
}

TEST(KdlInverseDynamics, ExampleArm) {
  if (SourceDir().empty()) GTEST_SKIP() << "INERTIAL_SOURCE_DIR is not set (run through ctest)";
  ExpectMatchesKdl(testing::ReadTextFile(SourceDir() + "/examples/arm7.urdf"), "arm7.urdf", 43);
}

TEST(KdlInverseDynamics, KukaLwr4) {
  const std::string path = SourceDir() + "/../shared/data/kuka_lwr4/kuka_lwr4.urdf";
  if (SourceDir().empty() || !std::filesystem::exists(path)) {
    GTEST_SKIP() << "the shared KUKA LWR4+ data (" << path << ") is not present";
  }
  ExpectMatchesKdl(testing::ReadTextFile(path), path, 47);
}

}  // namespace
}  // namespace inertial
