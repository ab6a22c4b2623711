// RobotModel (LoadUrdf / ParseUrdf + KinematicTree) against Orocos KDL's tree recursive Newton-Euler
// on the same URDF, converted to a KDL::Tree straight from urdfdom's model (formats/kdl_tree.hpp: no
// kdl_parser, and nothing of the code under test): the bundled example robots, the KUKA LWR4+ of
// the shared data when present, and random branched URDFs with fixed and prismatic joints and random
// rpy and axes.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "formats/kdl_tree.hpp"
#include "formats/urdf_text.hpp"
#include "inertial/formats/urdf_model.hpp"
#include "test_support.hpp"

namespace inertial {
namespace {

using testing::InertialXml;
using testing::JointXml;
using testing::KdlInverseDynamics;
using testing::LinkXml;
using testing::RelativeError;
using testing::Rng;
using testing::RobotXml;

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
    // One draw per statement, here and below, in the order the x86-64 build drew them (see testing::Rng).
    const double axis_z = rng.Normal();
    const double axis_y = rng.Normal();
    Vector3 axis(rng.Normal(), axis_y, axis_z);
    axis *= rng.Uniform(0.2, 3.0) / axis.norm();
    const Vector3 joint_rpy = rng.UniformVector<3>(-pi, pi);
    const Vector3 joint_xyz = rng.UniformVector<3>(-0.5, 0.5);
    body += JointXml("joint" + std::to_string(k), type, "link" + std::to_string(parent), name, joint_xyz, joint_rpy,
                     axis);
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
    const Vector3 com_rpy = rng.UniformVector<3>(-pi, pi);
    const Vector3 com_xyz = rng.UniformVector<3>(-0.2, 0.2);
    body += LinkXml(name, InertialXml(m, com_xyz, com_rpy, D));
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
