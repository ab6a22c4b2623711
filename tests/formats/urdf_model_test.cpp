#include "inertial/formats/urdf_model.hpp"
#include "inertial/formats/input_file.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <string>

#include "formats/urdf_text.hpp"
#include "test_support.hpp"

namespace inertial {
namespace {

using testing::InertialXml;
using testing::JointXml;
using testing::LinkXml;
using testing::Num;
using testing::RelativeError;
using testing::Rng;
using testing::RobotXml;

constexpr double kG = 9.81;

// URDF's rpy written out: R = Rz(yaw) Ry(pitch) Rx(roll), each elementary rotation by hand.
Matrix3 HandRpy(double roll, double pitch, double yaw) {
  Matrix3 Rx, Ry, Rz;
  Rx << 1, 0, 0, 0, std::cos(roll), -std::sin(roll), 0, std::sin(roll), std::cos(roll);
  Ry << std::cos(pitch), 0, std::sin(pitch), 0, 1, 0, -std::sin(pitch), 0, std::cos(pitch);
  Rz << std::cos(yaw), -std::sin(yaw), 0, std::sin(yaw), std::cos(yaw), 0, 0, 0, 1;
  return Rz * Ry * Rx;
}

// Parallel-axis term m (|d|^2 1 - d d^T).
Matrix3 Steiner(double m, const Vector3& d) { return m * (d.squaredNorm() * Matrix3::Identity() - d * d.transpose()); }

// pi in the project's order from m, c and the tensor about the origin.
Vector10 PiOf(double m, const Vector3& c, const Matrix3& I_o) {
  Vector10 pi;
  pi << m, m * c.x(), m * c.y(), m * c.z(), I_o(0, 0), I_o(1, 1), I_o(2, 2), I_o(0, 1), I_o(1, 2), I_o(0, 2);
  return pi;
}

using testing::ErrorOf;

const Matrix3 kSomeInertia = Vector3(0.02, 0.03, 0.04).asDiagonal();

// base -> joint `j` (type) -> link `b` with a plain inertial.
std::string OneJointRobot(const std::string& type, const std::string& extra = "") {
  return RobotXml("one", LinkXml("a") + LinkXml("b", InertialXml(1.0, Vector3(0.1, 0, 0), Vector3::Zero(), kSomeInertia)) +
                             JointXml("j", type, "a", "b", Vector3::Zero(), Vector3::Zero(), Vector3::UnitZ(), extra));
}

TEST(UrdfModel, BoxInertialWithComOffsetAndRotatedComFrame) {
  const double m = 2.5, a = 0.1, b = 0.2, c = 0.3;
  const Vector3 com(0.1, -0.05, 0.2), rpy(0.3, -0.4, 0.7);
  Matrix3 D = Matrix3::Zero();  // solid box about its centroid, along its edges
  D(0, 0) = m / 12 * (b * b + c * c);
  D(1, 1) = m / 12 * (a * a + c * c);
  D(2, 2) = m / 12 * (a * a + b * b);
  const std::string xml = RobotXml("box", LinkXml("base") + LinkXml("box", InertialXml(m, com, rpy, D)) +
                                              JointXml("j", "continuous", "base", "box"));
  const RobotModel model = ParseUrdf(xml, "box.urdf");

  const Matrix3 R = HandRpy(rpy.x(), rpy.y(), rpy.z());
  const Vector10 expected = PiOf(m, com, R * D * R.transpose() + Steiner(m, com));
  ASSERT_EQ(model.links.size(), 2u);
  EXPECT_EQ(model.links[1].link, "box");
  EXPECT_TRUE(model.links[1].present);
  EXPECT_FALSE(model.links[0].present);
  EXPECT_LT((model.links[1].pi.vector() - expected).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_LT((model.tree.inertia(0).vector() - expected).cwiseAbs().maxCoeff(), 1e-15);
}

TEST(UrdfModel, ProductsOfInertiaAreTensorEntries) {
  const double m = 1.5;
  const Vector3 c(0.2, 0.1, -0.3);
  Matrix3 I;  // as written: ixx .. izz about the COM, ixy etc. the off-diagonal tensor entries
  I << 0.05, -0.004, 0.003, -0.004, 0.06, 0.002, 0.003, 0.002, 0.07;
  const std::string xml = RobotXml("p", LinkXml("base") + LinkXml("l", InertialXml(m, c, Vector3::Zero(), I)) +
                                            JointXml("j", "continuous", "base", "l"));
  const Vector10 pi = ParseUrdf(xml, "p.urdf").links[1].pi.vector();
  EXPECT_NEAR(pi[pi_index::kMass], 1.5, 1e-15);
  EXPECT_NEAR(pi[pi_index::kHx], 1.5 * 0.2, 1e-15);
  EXPECT_NEAR(pi[pi_index::kHy], 1.5 * 0.1, 1e-15);
  EXPECT_NEAR(pi[pi_index::kHz], 1.5 * -0.3, 1e-15);
  EXPECT_NEAR(pi[pi_index::kIxx], 0.05 + 1.5 * (0.01 + 0.09), 1e-15);
  EXPECT_NEAR(pi[pi_index::kIyy], 0.06 + 1.5 * (0.04 + 0.09), 1e-15);
  EXPECT_NEAR(pi[pi_index::kIzz], 0.07 + 1.5 * (0.04 + 0.01), 1e-15);
  EXPECT_NEAR(pi[pi_index::kIxy], -0.004 - 1.5 * 0.2 * 0.1, 1e-15);
  EXPECT_NEAR(pi[pi_index::kIyz], 0.002 - 1.5 * 0.1 * -0.3, 1e-15);
  EXPECT_NEAR(pi[pi_index::kIxz], 0.003 - 1.5 * 0.2 * -0.3, 1e-15);
}

TEST(UrdfModel, JointTypesOriginsAndAxes) {
  const Vector3 xyz(0.1, -0.2, 0.3), rpy(-0.5, 0.25, 2.0);
  const std::string in = InertialXml(1.0, Vector3(0, 0, 0.1), Vector3::Zero(), kSomeInertia);
  const std::string no_axis =  // continuous without <axis>: URDF's default (1, 0, 0)
      "<joint name=\"j_cont\" type=\"continuous\"><parent link=\"l1\"/><child link=\"l2\"/></joint>\n";
  const std::string xml =
      RobotXml("joints", LinkXml("base") + LinkXml("l1", in) + LinkXml("l2", in) + LinkXml("l3", in) +
                             JointXml("j_rev", "revolute", "base", "l1", xyz, rpy, Vector3(0, 3, 4)) + no_axis +
                             JointXml("j_pris", "prismatic", "l2", "l3", Vector3::Zero(), Vector3::Zero(),
                                      Vector3(0, 0, -2)));
  const RobotModel model = ParseUrdf(xml, "joints.urdf");
  EXPECT_EQ(model.name, "joints");
  EXPECT_EQ(model.root_link, "base");
  ASSERT_EQ(model.tree.num_bodies(), 3);
  ASSERT_EQ(model.tree.num_dofs(), 3);
  EXPECT_EQ(model.dof_names, (std::vector<std::string>{"j_rev", "j_cont", "j_pris"}));
  EXPECT_EQ(model.body_links, (std::vector<std::string>{"l1", "l2", "l3"}));
  EXPECT_EQ(model.DofIndex("j_pris"), 2);
  EXPECT_EQ(model.DofIndex("nope"), -1);

  const JointModel& rev = model.tree.joint(0);
  EXPECT_EQ(rev.name, "j_rev");
  EXPECT_EQ(rev.type, JointType::kRevolute);
  EXPECT_LT((rev.R_parent_joint - HandRpy(-0.5, 0.25, 2.0)).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_LT((rev.p_parent_joint - xyz).cwiseAbs().maxCoeff(), 1e-16);
  EXPECT_LT((rev.axis - Vector3(0, 0.6, 0.8)).cwiseAbs().maxCoeff(), 1e-16);
  EXPECT_EQ(model.tree.parent(0), -1);

  EXPECT_EQ(model.tree.joint(1).type, JointType::kRevolute);
  EXPECT_EQ(model.tree.joint(1).axis, Vector3(1, 0, 0));
  EXPECT_EQ(model.tree.parent(1), 0);
  EXPECT_EQ(model.tree.joint(2).type, JointType::kPrismatic);
  EXPECT_EQ(model.tree.joint(2).axis, Vector3(0, 0, -1));
  EXPECT_EQ(model.tree.parent(2), 1);
}

TEST(UrdfModel, PendulumAndSliderTorquesByHand) {
  // Pendulum about y, COM at (l, 0, 0): tau = (Iyy_com + m l^2) qdd - m g l cos q.
  const double m = 1.2, l = 0.4;
  const Matrix3 I_com = Vector3(0.015, 0.02, 0.03).asDiagonal();
  const RobotModel pendulum = ParseUrdf(
      RobotXml("pendulum", LinkXml("base") + LinkXml("arm", InertialXml(m, Vector3(l, 0, 0), Vector3::Zero(), I_com)) +
                               JointXml("hinge", "continuous", "base", "arm", Vector3::Zero(), Vector3::Zero(),
                                        Vector3::UnitY())),
      "pendulum.urdf");
  // Slider along z: tau = m (qdd + g), whatever q and qd.
  const RobotModel slider = ParseUrdf(
      RobotXml("slider", LinkXml("base") + LinkXml("cart", InertialXml(m, Vector3(0.3, 0.1, 0), Vector3(0.1, 0.2, 0.3), I_com)) +
                             JointXml("rail", "prismatic", "base", "cart", Vector3(1, 2, 3))),
      "slider.urdf");
  Rng rng(11);
  for (int k = 0; k < 10; ++k) {
    Eigen::VectorXd q(1), qd(1), qdd(1);
    q << rng.Uniform(-3, 3);
    qd << rng.Uniform(-2, 2);
    qdd << rng.Uniform(-5, 5);
    EXPECT_NEAR(pendulum.tree.InverseDynamics(q, qd, qdd)[0], (0.02 + m * l * l) * qdd[0] - m * kG * l * std::cos(q[0]),
                1e-12);
    EXPECT_NEAR(slider.tree.InverseDynamics(q, qd, qdd)[0], m * (qdd[0] + kG), 1e-12);
  }
}

// link1 (moving) carries `tip` by a rotated fixed joint; link2 moves on a joint hanging from tip; a
// massless marker is fixed to tip. The hand-merged version puts everything of tip into link1.
TEST(UrdfModel, FixedChildMergesLikeTheHandMergedLink) {
  const double m1 = 2.0, m2 = 0.7, m3 = 1.0, theta = 0.5, phi = 0.3;
  const Vector3 c1(0.1, 0, 0.05), c2(0.05, 0.01, 0), c3(0.2, 0, 0);
  const Matrix3 I1 = Vector3(0.01, 0.02, 0.025).asDiagonal(), I2 = Vector3(0.002, 0.003, 0.004).asDiagonal(),
                I3 = Vector3(0.001, 0.01, 0.01).asDiagonal();
  const Vector3 p_mount(0.3, 0.02, 0), p_j2(0.1, 0, 0), p_marker(0.12, 0, 0);
  const std::string common = LinkXml("base") + JointXml("j1", "continuous", "base", "link1", Vector3(0, 0, 0.3)) +
                             LinkXml("link2", InertialXml(m3, c3, Vector3::Zero(), I3));
  const std::string with_fixed =
      RobotXml("fixed", common + LinkXml("link1", InertialXml(m1, c1, Vector3::Zero(), I1)) +
                            JointXml("mount", "fixed", "link1", "tip", p_mount, Vector3(0, 0, theta)) +
                            LinkXml("tip", InertialXml(m2, c2, Vector3::Zero(), I2)) +
                            JointXml("j2", "continuous", "tip", "link2", p_j2, Vector3(0, 0, phi), Vector3::UnitY()) +
                            JointXml("marker_fixed", "fixed", "tip", "marker", p_marker) + LinkXml("marker"));

  // By hand: tip's COM and tensor in link1's frame, then one body about the common COM.
  const Matrix3 Rz = HandRpy(0, 0, theta);
  const Vector3 c2_in_1 = p_mount + Rz * c2;
  const double m = m1 + m2;
  const Vector3 com = (m1 * c1 + m2 * c2_in_1) / m;
  const Matrix3 I_merged = I1 + Steiner(m1, c1 - com) + Rz * I2 * Rz.transpose() + Steiner(m2, c2_in_1 - com);
  const std::string merged =
      RobotXml("merged", common + LinkXml("link1", InertialXml(m, com, Vector3::Zero(), I_merged)) +
                             JointXml("j2", "continuous", "link1", "link2", p_mount + Rz * p_j2,
                                      Vector3(0, 0, theta + phi), Vector3::UnitY()));

  const RobotModel a = ParseUrdf(with_fixed, "fixed.urdf");
  const RobotModel b = ParseUrdf(merged, "merged.urdf");
  ASSERT_EQ(a.tree.num_dofs(), 2);
  ASSERT_EQ(b.tree.num_dofs(), 2);
  EXPECT_EQ(a.body_links, (std::vector<std::string>{"link1", "link2"}));
  EXPECT_EQ(a.body_has_inertial, (std::vector<bool>{true, true}));
  EXPECT_EQ(a.links.size(), 5u);
  EXPECT_EQ(a.BodyIndex("tip"), 0);
  EXPECT_EQ(a.BodyIndex("marker"), 0);
  EXPECT_EQ(a.BodyIndex("link2"), 1);
  EXPECT_EQ(a.BodyIndex("base"), -1);
  EXPECT_EQ(a.BodyIndex("no_such_link"), -1);
  const SpatialTransform X_marker = a.LinkInBody("marker");
  EXPECT_LT((X_marker.R_AB - Rz).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_LT((X_marker.p_AB - (p_mount + Rz * p_marker)).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_THROW(a.LinkInBody("no_such_link"), std::invalid_argument);

  Rng rng(5);
  for (int k = 0; k < 20; ++k) {
    const Eigen::VectorXd q = rng.UniformVector<2>(-3, 3), qd = rng.UniformVector<2>(-2, 2),
                          qdd = rng.UniformVector<2>(-5, 5);
    const Vector3 g = rng.UniformVector<3>(-10, 10);
    EXPECT_LT(RelativeError(a.tree.InverseDynamics(q, qd, qdd, g), b.tree.InverseDynamics(q, qd, qdd, g)), 1e-12);
  }
}

TEST(UrdfModel, BranchesInParentFirstFileOrderAndLinksFixedToTheRoot) {
  const auto in = [](double m) { return InertialXml(m, Vector3(0.05, 0.02, 0.1), Vector3(0.1, 0.2, 0.3), kSomeInertia); };
  const std::string left = JointXml("left_1", "continuous", "pedestal", "L1", Vector3(0, 0.2, 0.1), Vector3(0.3, 0, 0)) +
                           LinkXml("L1", in(1.0)) +
                           JointXml("left_2", "revolute", "L1", "L2", Vector3(0, 0, 0.4), Vector3(0, 0, 0), Vector3::UnitY()) +
                           LinkXml("L2", in(0.8));
  const std::string pedestal = LinkXml("base") + JointXml("pedestal_fixed", "fixed", "base", "pedestal", Vector3(0, 0, 0.5)) +
                               LinkXml("pedestal", in(50.0));
  // The right branch's second joint comes first in the file.
  const std::string right =
      JointXml("right_2", "prismatic", "R1", "R2", Vector3(0.1, 0, 0.3), Vector3(0, 0.2, 0), Vector3::UnitX()) +
      LinkXml("R2", in(0.6)) +
      JointXml("right_1", "continuous", "pedestal", "R1", Vector3(0, -0.2, 0.1), Vector3(-0.3, 0, 0)) +
      LinkXml("R1", in(1.1));
  const RobotModel both = ParseUrdf(RobotXml("two_arms", pedestal + left + right), "two_arms.urdf");
  const RobotModel left_only = ParseUrdf(RobotXml("left", pedestal + left), "left.urdf");
  const RobotModel right_only = ParseUrdf(RobotXml("right", pedestal + right), "right.urdf");

  EXPECT_EQ(both.dof_names, (std::vector<std::string>{"left_1", "left_2", "right_1", "right_2"}));
  EXPECT_EQ(both.tree.parent(1), 0);
  EXPECT_EQ(both.tree.parent(2), -1);
  EXPECT_EQ(both.tree.parent(3), 2);
  EXPECT_EQ(both.BodyIndex("pedestal"), -1);
  EXPECT_EQ(both.BodyIndex("R2"), 3);
  EXPECT_EQ(both.LinkInBody("pedestal").p_AB, Vector3(0, 0, 0.5));

  // Fixed base: each branch's torques are those of the branch alone.
  Rng rng(17);
  for (int k = 0; k < 20; ++k) {
    const Eigen::VectorXd q = rng.UniformVector<4>(-2, 2), qd = rng.UniformVector<4>(-2, 2),
                          qdd = rng.UniformVector<4>(-5, 5);
    const Eigen::VectorXd tau = both.tree.InverseDynamics(q, qd, qdd);
    EXPECT_LT(RelativeError(tau.head<2>(), left_only.tree.InverseDynamics(q.head<2>(), qd.head<2>(), qdd.head<2>())),
              1e-12);
    EXPECT_LT(RelativeError(tau.tail<2>(), right_only.tree.InverseDynamics(q.tail<2>(), qd.tail<2>(), qdd.tail<2>())),
              1e-12);
  }
}

TEST(UrdfModel, MasslessAndZeroInertialLinksFixedToAMovingLinkAreFine) {
  const std::string xml = RobotXml(
      "tool", LinkXml("base") + LinkXml("l", InertialXml(1.0, Vector3(0.1, 0, 0), Vector3::Zero(), kSomeInertia)) +
                  JointXml("j", "continuous", "base", "l") + JointXml("f1", "fixed", "l", "flange", Vector3(0.2, 0, 0)) +
                  LinkXml("flange") + JointXml("f2", "fixed", "flange", "tcp", Vector3(0, 0, 0.1)) +
                  LinkXml("tcp", InertialXml(0.0, Vector3::Zero(), Vector3::Zero(), Matrix3::Zero())));
  const RobotModel model = ParseUrdf(xml, "tool.urdf");
  EXPECT_EQ(model.tree.num_bodies(), 1);
  EXPECT_EQ(model.BodyIndex("tcp"), 0);
  EXPECT_EQ(model.LinkInBody("tcp").p_AB, Vector3(0.2, 0, 0.1));
  EXPECT_LT((model.tree.inertia(0).vector() - model.links[1].pi.vector()).cwiseAbs().maxCoeff(), 1e-16);
}

// --- errors ---

TEST(UrdfModelErrors, MissingFileAndDirectoryNameThePath) {
  const std::string missing = "/nonexistent_dir_for_inertial/robot.urdf";
  const std::string message = ErrorOf([&] { LoadUrdf(missing); });
  EXPECT_EQ(message, "cannot read the URDF '" + missing + "': No such file or directory");
  const std::string dir = std::filesystem::temp_directory_path().string();
  EXPECT_EQ(ErrorOf([&] { LoadUrdf(dir); }), "cannot read the URDF '" + dir + "': Is a directory");
}

TEST(UrdfModelErrors, BrokenXmlSaysWhereAndWhy) {
  const std::string message = ErrorOf([] { ParseUrdf("<robot name='r'>\n<link name='a'>\n</robot>", "broken.urdf"); });
  EXPECT_EQ(message.rfind("broken.urdf: is not a valid URDF: XML error at line", 0), 0u) << message;
}

TEST(UrdfModelErrors, NotARobotDocument) {
  const std::string message = ErrorOf([] { ParseUrdf("<sdf version='1.6'/>", "world.sdf"); });
  EXPECT_EQ(message.rfind("world.sdf: is not a valid URDF", 0), 0u) << message;
  EXPECT_NE(message.find("<sdf>"), std::string::npos) << message;
}

TEST(UrdfModelErrors, UrdfdomRejectionsCarryUrdfdomsReason) {
  // urdfdom requires <limit> on revolute joints and says so.
  const std::string xml = RobotXml("r", LinkXml("a") + LinkXml("b", InertialXml(1, Vector3::Zero(), Vector3::Zero(), kSomeInertia)) +
                                            "<joint name=\"elbow\" type=\"revolute\"><parent link=\"a\"/><child link=\"b\"/></joint>");
  const std::string message = ErrorOf([&] { ParseUrdf(xml, "nolimit.urdf"); });
  EXPECT_EQ(message.rfind("nolimit.urdf: is not a valid URDF: ", 0), 0u) << message;
  EXPECT_NE(message.find("elbow"), std::string::npos) << message;
  EXPECT_NE(message.find("limits"), std::string::npos) << message;
}

// urdfdom hands some attribute text to console_bridge's printf-style logger as the format itself:
// '%s%n' wrote through a stack pointer (a segfault) and '%x%x%x%x' leaked stack contents into the
// message. Every attribute urdfdom reads is checked first: no '%', numbers parsed strictly, counted.
TEST(UrdfModelErrors, FormatStringsAndMalformedNumbersAreRefusedBeforeUrdfdom) {
  const std::string inertia = "<inertia ixx='1' iyy='1' izz='1' ixy='0' ixz='0' iyz='0'/>";
  struct Case {
    std::string link_inside, expected;
  };
  const Case cases[] = {
      {"<inertial><mass value=\"%s%n\"/>" + inertia + "</inertial>", "<mass> (line"},
      {"<inertial><origin xyz=\"%x%x%x%x\"/><mass value=\"1\"/>" + inertia + "</inertial>", "'%'"},
      {"<inertial><mass value=\"1kg\"/>" + inertia + "</inertial>", "attribute 'value': '1kg' is not a number"},
      {"<inertial><mass value=\"nan\"/>" + inertia + "</inertial>", "attribute 'value'"},
      {"<inertial><origin xyz=\"0 0\"/><mass value=\"1\"/>" + inertia + "</inertial>", "holds 2 numbers, 3 expected"},
      {"<inertial><mass value=\"1\"/><inertia ixx='1e999' iyy='1' izz='1' ixy='0' ixz='0' iyz='0'/></inertial>",
       "attribute 'ixx'"},
      {"<visual><geometry><box size=\"1 %n 1\"/></geometry></visual><inertial><mass value=\"1\"/>" + inertia +
           "</inertial>",
       "<box> (line"},
  };
  for (const Case& c : cases) {
    const std::string xml = RobotXml("r", LinkXml("a") + LinkXml("forearm", c.link_inside) + JointXml("j", "continuous", "a", "forearm"));
    const std::string message = ErrorOf([&] { ParseUrdf(xml, "evil.urdf"); });
    EXPECT_EQ(message.rfind("evil.urdf: ", 0), 0u) << message;
    EXPECT_NE(message.find(c.expected), std::string::npos) << c.link_inside << " -> " << message;
    EXPECT_EQ(message.find("0x"), std::string::npos) << "stack contents leaked: " << message;
  }
  // A '%' in a name is refused as well (urdfdom logs names in its errors).
  const std::string named = RobotXml("r", LinkXml("a") + LinkXml("fore%sarm", "<inertial><mass value='1'/>" + inertia + "</inertial>") +
                                              JointXml("j", "continuous", "a", "fore%sarm"));
  EXPECT_NE(ErrorOf([&] { ParseUrdf(named, "evil.urdf"); }).find("holds a '%'"), std::string::npos);
}

// Joints that do not form a tree are refused before urdfdom links them (its links then hold each
// other by shared pointers and leaked when it refused the file; found by tests/fuzz/urdf_fuzz.cpp).
TEST(UrdfModelErrors, JointsThatDoNotFormATreeAreRefusedBeforeUrdfdom) {
  const std::string links = LinkXml("base") + LinkXml("a") + LinkXml("b");
  const struct { std::string joints, expected; } cases[] = {
      {JointXml("j", "continuous", "base", "a") + JointXml("k", "continuous", "b", "b"),
       "joint 'k' (line"},
      {JointXml("j", "continuous", "base", "a") + JointXml("k", "continuous", "base", "a"),
       "link 'a' is already the child of joint 'j'"},
      {JointXml("j", "continuous", "a", "b") + JointXml("k", "continuous", "b", "a"), "the joints form a loop through link"},
  };
  for (const auto& c : cases) {
    const std::string message = ErrorOf([&] { ParseUrdf(RobotXml("r", links + c.joints), "loop.urdf"); });
    EXPECT_EQ(message.rfind("loop.urdf: ", 0), 0u) << message;
    EXPECT_NE(message.find(c.expected), std::string::npos) << message;
  }
  EXPECT_NE(ErrorOf([&] { ParseUrdf(RobotXml("r", links + JointXml("k", "continuous", "b", "b")), "self.urdf"); })
                .find("link 'b' is both its parent and its child"),
            std::string::npos);
}

TEST(UrdfModelErrors, InertialWithoutMassIsInvalidAlthoughUrdfdomKeepsIt) {
  const std::string xml = RobotXml(
      "r", LinkXml("a") + LinkXml("forearm", "<inertial><inertia ixx='1' iyy='1' izz='1' ixy='0' ixz='0' iyz='0'/></inertial>") +
               JointXml("j", "continuous", "a", "forearm"));
  const std::string message = ErrorOf([&] { ParseUrdf(xml, "nomass.urdf"); });
  EXPECT_EQ(message.rfind("nomass.urdf: is not a valid URDF: ", 0), 0u) << message;
  EXPECT_NE(message.find("mass"), std::string::npos) << message;
  EXPECT_NE(message.find("forearm"), std::string::npos) << message;
}

TEST(UrdfModelErrors, MovingLinkWithoutInertial) {
  const std::string xml = RobotXml("r", LinkXml("a") + LinkXml("forearm") + JointXml("elbow", "continuous", "a", "forearm"));
  const std::string message = ErrorOf([&] { ParseUrdf(xml, "bare.urdf"); });
  EXPECT_EQ(message, "bare.urdf: link 'forearm' (moved by joint 'elbow') has no <inertial>, nor has any link fixed to it");

  UrdfLoadOptions lenient;
  lenient.require_consistent_inertials = false;
  const RobotModel model = ParseUrdf(xml, "bare.urdf", lenient);
  EXPECT_EQ(model.body_has_inertial, std::vector<bool>{false});
  EXPECT_EQ(model.tree.inertia(0).vector(), Vector10::Zero());
}

TEST(UrdfModelErrors, InconsistentInertialNamesTheLinkAndTheFailedCheck) {
  const Matrix3 flat = Vector3(0.01, 0.01, 0.03).asDiagonal();  // Dx + Dy < Dz
  const std::string xml = RobotXml("r", LinkXml("a") + LinkXml("thigh", InertialXml(2.0, Vector3(0, 0, -0.1), Vector3(0.2, 0, 0), flat)) +
                                            JointXml("hip", "continuous", "a", "thigh"));
  const std::string message = ErrorOf([&] { ParseUrdf(xml, "leg.urdf"); });
  EXPECT_EQ(message.rfind("leg.urdf: link 'thigh': <inertial> is not physically consistent: ", 0), 0u) << message;
  EXPECT_NE(message.find("triangle"), std::string::npos) << message;

  const std::string negative = RobotXml("r", LinkXml("a") + LinkXml("shank", InertialXml(-1.0, Vector3::Zero(), Vector3::Zero(), kSomeInertia)) +
                                                 JointXml("knee", "continuous", "a", "shank"));
  const std::string message2 = ErrorOf([&] { ParseUrdf(negative, "leg.urdf"); });
  EXPECT_EQ(message2.rfind("leg.urdf: link 'shank': <inertial> is not physically consistent: ", 0), 0u) << message2;
  EXPECT_NE(message2.find("mass"), std::string::npos) << message2;

  UrdfLoadOptions lenient;
  lenient.require_consistent_inertials = false;
  EXPECT_NO_THROW(ParseUrdf(xml, "leg.urdf", lenient));
  EXPECT_NO_THROW(ParseUrdf(negative, "leg.urdf", lenient));
}

TEST(UrdfModelErrors, InertialsOfTheBaseAreIgnored) {
  const Matrix3 flat = Vector3(0.01, 0.01, 0.03).asDiagonal();
  const std::string xml = RobotXml("r", LinkXml("a", InertialXml(-5, Vector3::Zero(), Vector3::Zero(), flat)) +
                                            JointXml("f", "fixed", "a", "plate") + LinkXml("plate", InertialXml(1, Vector3::Zero(), Vector3::Zero(), flat)) +
                                            LinkXml("b", InertialXml(1, Vector3::Zero(), Vector3::Zero(), kSomeInertia)) +
                                            JointXml("j", "continuous", "plate", "b"));
  EXPECT_NO_THROW(ParseUrdf(xml, "base.urdf"));
}

TEST(UrdfModelErrors, FloatingAndPlanarJointsAreNotSupportedYet) {
  for (const std::string type : {"floating", "planar"}) {
    const std::string message = ErrorOf([&] { ParseUrdf(OneJointRobot(type), "free.urdf"); });
    EXPECT_EQ(message.rfind("free.urdf: joint 'j' is " + type, 0), 0u) << message;
    EXPECT_NE(message.find("floating-base and planar joints are not supported yet"), std::string::npos) << message;
  }
}

TEST(UrdfModelErrors, MimicJointsAreNotSupported) {
  const std::string xml =
      RobotXml("r", LinkXml("a") + LinkXml("b", InertialXml(1, Vector3::Zero(), Vector3::Zero(), kSomeInertia)) +
                        LinkXml("c", InertialXml(1, Vector3::Zero(), Vector3::Zero(), kSomeInertia)) +
                        JointXml("finger_1", "continuous", "a", "b") +
                        JointXml("finger_2", "continuous", "b", "c", Vector3::Zero(), Vector3::Zero(), Vector3::UnitZ(),
                                 "<mimic joint=\"finger_1\" multiplier=\"1\"/>"));
  const std::string message = ErrorOf([&] { ParseUrdf(xml, "gripper.urdf"); });
  EXPECT_EQ(message.rfind("gripper.urdf: joint 'finger_2' has <mimic>", 0), 0u) << message;
  EXPECT_NE(message.find("not supported"), std::string::npos) << message;
}

TEST(UrdfModelErrors, ZeroAxis) {
  const std::string xml = RobotXml("r", LinkXml("a") + LinkXml("b", InertialXml(1, Vector3::Zero(), Vector3::Zero(), kSomeInertia)) +
                                            JointXml("wrist", "continuous", "a", "b", Vector3::Zero(), Vector3::Zero(), Vector3::Zero()));
  EXPECT_EQ(ErrorOf([&] { ParseUrdf(xml, "axis.urdf"); }), "axis.urdf: joint 'wrist': <axis> is the zero vector");
}

TEST(UrdfModelErrors, FileErrorsStartWithThePath) {
  const std::filesystem::path path = testing::TempUrdfPath("floating.urdf");
  testing::WriteTextFile(path, OneJointRobot("floating"));
  const std::string message = ErrorOf([&] { LoadUrdf(path.string()); });
  std::filesystem::remove(path);
  EXPECT_EQ(message.rfind(path.string() + ": joint 'j' is floating", 0), 0u) << message;
}

// --- input limits (issue 35): what a blind fuzzer found, each refused at once ---

// The one-joint robot's text without its XML declaration.
std::string RobotElementOnly() {
  std::string xml = OneJointRobot("continuous");
  return xml.substr(xml.find("<robot"));
}

// "<?xml " then 100,000 nested elements, then "?>" and a valid robot: tinyxml2 saw one declaration
// node, urdfdom's TinyXML recursed once per level and overflowed the stack (SIGSEGV after 7-13 s).
TEST(UrdfModelInputLimits, ElementsInsideABrokenXmlDeclarationAreRefusedAtOnce) {
  std::string xml = "<?xml ";
  for (int k = 0; k < 100000; ++k) xml += "<a>";
  xml += "?>" + RobotElementOnly();
  std::string message;
  const double seconds = testing::SecondsOf([&] { message = ErrorOf([&] { ParseUrdf(xml, "deep.urdf"); }); });
  EXPECT_EQ(message,
            "deep.urdf: is not a valid URDF: the processing instruction at line 1 is not an XML declaration "
            "(<?xml version=\"1.0\" encoding=\"...\"?>, first in the file)");
  EXPECT_LT(seconds, testing::kPromptSeconds);
}

TEST(UrdfModelInputLimits, ElementsInsideAProcessingInstructionAnywhereAreRefused) {
  std::string inner;
  for (int k = 0; k < 100000; ++k) inner += "<a>";
  // Before the root: tinyxml2 reads it as one node, refused here.
  std::string message;
  double seconds = testing::SecondsOf([&] { message = ErrorOf([&] { ParseUrdf("<?pi " + inner + "?>" + RobotElementOnly(), "pi.urdf"); }); });
  EXPECT_EQ(message, "pi.urdf: is not a valid URDF: the processing instruction at line 1 holds a '<' (an element inside \"<?...?>\")");
  EXPECT_LT(seconds, testing::kPromptSeconds);
  // Inside <robot>: tinyxml2 refuses any "<?...?>".
  std::string xml = RobotElementOnly();
  xml.insert(xml.find('>') + 1, "<?pi " + inner + "?>");
  seconds = testing::SecondsOf([&] { message = ErrorOf([&] { ParseUrdf(xml, "pi.urdf"); }); });
  EXPECT_EQ(message.rfind("pi.urdf: is not a valid URDF: XML error at line 1: XML_ERROR_PARSING_DECLARATION", 0), 0u) << message;
  EXPECT_LT(seconds, testing::kPromptSeconds);
  // A second XML declaration is not one, nor is one of another grammar.
  EXPECT_NE(ErrorOf([&] { ParseUrdf("<?xml version=\"1.0\"?>\n<?xml version=\"1.0\"?>" + RobotElementOnly(), "two.urdf"); })
                .find("line 2 is not an XML declaration"),
            std::string::npos);
  EXPECT_NE(ErrorOf([&] { ParseUrdf("<?xml version=\"1.0\" encoding=\"utf 8\"?>" + RobotElementOnly(), "enc.urdf"); })
                .find("line 1 is not an XML declaration"),
            std::string::npos);
}

TEST(UrdfModelInputLimits, PlainDeepNestingIsRefusedByDepth) {
  std::string inner;
  for (int k = 0; k < 100000; ++k) inner += "<a>";
  std::string xml = RobotElementOnly();
  xml.insert(xml.find('>') + 1, inner);
  std::string message;
  const double seconds = testing::SecondsOf([&] { message = ErrorOf([&] { ParseUrdf(xml, "nest.urdf"); }); });
  EXPECT_EQ(message.rfind("nest.urdf: is not a valid URDF: XML error at line 1: XML_ELEMENT_DEPTH_EXCEEDED", 0), 0u) << message;
  EXPECT_LT(seconds, testing::kPromptSeconds);
}

// Declarations, instructions, comments and a DOCTYPE as real files have them leave the model as it is.
TEST(UrdfModelInputLimits, WellFormedDeclarationsCommentsAndDoctypeAreRead) {
  const RobotModel plain = ParseUrdf(RobotElementOnly(), "plain.urdf");
  for (const std::string& head :
       {std::string("<?xml version='1.0' encoding='UTF-8' standalone=\"yes\" ?>\n"),
        std::string("<?xml version=\"1.1\"?><?xml-stylesheet type=\"text/xsl\" href=\"r.xsl\"?><!DOCTYPE robot>\n<!-- <a> -->")}) {
    std::string xml = head + RobotElementOnly();
    xml.insert(xml.find("<link"), "<!-- a comment with <link name=\"fake\"/> in it -->");
    const RobotModel model = ParseUrdf(xml, "declared.urdf");
    EXPECT_EQ(model.dof_names, plain.dof_names) << head;
    EXPECT_EQ(model.links.size(), plain.links.size()) << head;
    EXPECT_EQ(model.tree.inertia(0).vector(), plain.tree.inertia(0).vector()) << head;
  }
  // A version of 100,000 digits is a version by the grammar; its check must not recurse per
  // character (a std::regex did, and overflowed the stack: tests/fuzz/corpus/urdf/long_xml_version_*).
  const std::string long_version = "<?xml version=\"1." + std::string(100000, '0') + "\"?>";
  EXPECT_EQ(ParseUrdf(long_version + RobotElementOnly(), "long.urdf").dof_names, plain.dof_names);
  EXPECT_NE(ErrorOf([&] { ParseUrdf(long_version.substr(0, 50000) + "x\"?>" + RobotElementOnly(), "long.urdf"); })
                .find("is not an XML declaration"),
            std::string::npos);
}

// Positions and sizes beyond any robot (kMaxUrdfLength, 1000 m) are refused where they are written.
TEST(UrdfModelInputLimits, LengthsBeyondAnyRobotAreRefusedNamingTheElement) {
  const std::string inertial = InertialXml(1.0, Vector3::Zero(), Vector3::Zero(), kSomeInertia);
  const struct {
    std::string b_inside, joint_origin, expected;
  } cases[] = {
      {inertial, "0 0 1e300", "joint 'j': <origin> (line 5): attribute 'xyz' holds 1e+300 m, beyond the 1000 m of any robot"},
      {inertial, "-1000.5 0 0", "joint 'j': <origin> (line 5): attribute 'xyz' holds -1000.5 m"},
      {InertialXml(1.0, Vector3(0, 2000, 0), Vector3::Zero(), kSomeInertia), "0 0 0", "link 'b': <origin> (line"},
      {"<visual><geometry><box size=\"0.1 0.1 1200\"/></geometry></visual>" + inertial, "0 0 0", "link 'b': <box> (line"},
      {"<collision><geometry><cylinder radius=\"0.05\" length=\"1e4\"/></geometry></collision>" + inertial, "0 0 0",
       "attribute 'length' holds 10000 m"},
      {"<visual><geometry><sphere radius=\"-1e5\"/></geometry></visual>" + inertial, "0 0 0", "attribute 'radius' holds -1e+05 m"},
      {inertial, "0 0 0\"/><limit lower=\"-1e300\" upper=\"1\" effort=\"1\" velocity=\"1",
       "joint 'j': <limit> (line 5): attribute 'lower' holds -1e+300 m or rad, beyond the 1000 m or rad of any robot"},
  };
  for (const auto& c : cases) {
    const std::string xml = RobotXml("r", LinkXml("a") + LinkXml("b", c.b_inside) +
                                              "<joint name=\"j\" type=\"continuous\"><parent link=\"a\"/><child link=\"b\"/>"
                                              "<origin xyz=\"" + c.joint_origin + "\"/></joint>");
    const std::string message = ErrorOf([&] { ParseUrdf(xml, "far.urdf"); });
    EXPECT_EQ(message.rfind("far.urdf: ", 0), 0u) << message;
    EXPECT_NE(message.find(c.expected), std::string::npos) << message;
  }
  // 1000 m itself is a length a URDF may state (a joint 1 km away is odd, not impossible to write).
  const RobotModel far = ParseUrdf(RobotXml("r", LinkXml("a") + LinkXml("b", inertial) +
                                                     "<joint name=\"j\" type=\"continuous\"><parent link=\"a\"/>"
                                                     "<child link=\"b\"/><origin xyz=\"0 0 -1000\"/></joint>"),
                                   "km.urdf");
  EXPECT_EQ(far.tree.joint(0).p_parent_joint, Vector3(0, 0, -1000));
}

// Costs that grow faster than the file: attributes per tag (tinyxml2 alone took 8 s for 60,000 on
// one tag) and links (a chain written children first is placed in their square).
TEST(UrdfModelInputLimits, TagsWithTooManyAttributesAndRobotsWithTooManyLinksAreRefused) {
  std::string attributes;
  for (int k = 0; k < 60000; ++k) attributes += " a" + std::to_string(k) + "=\"\"";
  std::string xml = RobotElementOnly();
  xml.insert(xml.find("<link") + 5, attributes);
  std::string message;
  const double seconds = testing::SecondsOf([&] { message = ErrorOf([&] { ParseUrdf(xml, "attrs.urdf"); }); });
  EXPECT_EQ(message, "attrs.urdf: is not a valid URDF: the tag at line 2 has more than 32 attributes");
  EXPECT_LT(seconds, testing::kPromptSeconds);
  // '=' inside quoted values, comments, CDATA and declarations are not attributes.
  xml = RobotElementOnly();
  xml.insert(xml.find("<link"), "<!-- " + std::string(100, '=') + " --><![CDATA[" + std::string(100, '=') + "]]>");
  xml.insert(xml.find("<link") + 5, " note=\"" + std::string(100, '=') + "\"");
  EXPECT_NO_THROW(ParseUrdf(xml, "quoted.urdf"));

  std::string links = LinkXml("l0"), joints;
  for (int k = 1; k <= kMaxUrdfLinks; ++k) {
    links += LinkXml("l" + std::to_string(k), InertialXml(1.0, Vector3::Zero(), Vector3::Zero(), kSomeInertia));
    joints += JointXml("j" + std::to_string(k), "continuous", "l" + std::to_string(k - 1), "l" + std::to_string(k));
  }
  EXPECT_EQ(ErrorOf([&] { ParseUrdf(RobotXml("r", links + joints), "many.urdf"); }),
            "many.urdf: has 2001 links and 2000 joints, more than the 2000 of any robot");
}

TEST(UrdfModelInputLimits, FilesAndTextOverTheSizeLimitAreRefusedBeforeParsing) {
  // A valid robot padded with a comment to one byte over kMaxUrdfBytes.
  std::string xml = OneJointRobot("continuous");
  xml += "<!--" + std::string(kMaxUrdfBytes - xml.size() - 7 + 1, 'x') + "-->";
  ASSERT_EQ(xml.size(), kMaxUrdfBytes + 1);
  const std::string expected = "big.urdf: the URDF is 16777217 bytes, over its limit of 16 MiB: refused before parsing";
  EXPECT_EQ(ErrorOf([&] { ParseUrdf(xml, "big.urdf"); }), expected);
  const std::filesystem::path path = testing::TempUrdfPath("big.urdf");
  testing::WriteTextFile(path, xml);
  std::string message;
  const double seconds = testing::SecondsOf([&] { message = ErrorOf([&] { LoadUrdf(path.string()); }); });
  EXPECT_EQ(message, path.string() + ": the URDF is 16777217 bytes, over its limit of 16 MiB: refused before parsing");
  EXPECT_LT(seconds, testing::kPromptSeconds);
  // One byte less is read.
  xml.erase(xml.size() - 5, 1);
  testing::WriteTextFile(path, xml);
  EXPECT_EQ(LoadUrdf(path.string()).dof_names, std::vector<std::string>{"j"});
  std::filesystem::remove(path);
}

// --- joint limits ---

// The one-joint robot with `limit` in place of the helper's <limit lower="-3" upper="3" ...>.
std::string WithLimit(const std::string& type, const std::string& limit) {
  std::string xml = OneJointRobot(type);
  const std::string stock = "<limit lower=\"-3\" upper=\"3\" effort=\"100\" velocity=\"10\"/>";
  const std::size_t at = xml.find(stock);
  if (at != std::string::npos) {
    xml.replace(at, stock.size(), limit);
  } else {
    xml.insert(xml.find("</joint>"), limit);
  }
  return xml;
}

TEST(UrdfModelLimits, ReadsEveryStatedLimitAndNothingElse) {
  const RobotModel stock = ParseUrdf(OneJointRobot("revolute"), "r.urdf");
  ASSERT_EQ(stock.dof_limits.size(), 1u);
  EXPECT_EQ(stock.dof_limits[0].lower, -3.0);
  EXPECT_EQ(stock.dof_limits[0].upper, 3.0);
  EXPECT_EQ(stock.dof_limits[0].velocity, 10.0);
  EXPECT_EQ(stock.dof_limits[0].effort, 100.0);
  // Absent attributes and a 0 velocity or effort state no limit (urdfdom would read lower = 0).
  const RobotModel open = ParseUrdf(WithLimit("prismatic", "<limit upper=\"0.25\" effort=\"0\" velocity=\"0.5\"/>"), "p.urdf");
  EXPECT_TRUE(std::isinf(open.dof_limits[0].lower) && open.dof_limits[0].lower < 0);
  EXPECT_EQ(open.dof_limits[0].upper, 0.25);
  EXPECT_EQ(open.dof_limits[0].velocity, 0.5);
  EXPECT_TRUE(std::isinf(open.dof_limits[0].effort));
  // A continuous joint has no position range whatever <limit> says.
  const RobotModel wheel = ParseUrdf(WithLimit("continuous", "<limit lower=\"-1\" upper=\"1\" effort=\"7\" velocity=\"3\"/>"), "c.urdf");
  EXPECT_TRUE(std::isinf(wheel.dof_limits[0].lower) && std::isinf(wheel.dof_limits[0].upper));
  EXPECT_EQ(wheel.dof_limits[0].velocity, 3.0);
  EXPECT_EQ(wheel.dof_limits[0].effort, 7.0);
  const RobotModel bare = ParseUrdf(OneJointRobot("continuous"), "c.urdf");
  EXPECT_TRUE(std::isinf(bare.dof_limits[0].velocity) && std::isinf(bare.dof_limits[0].effort));
}

TEST(UrdfModelLimits, RefusesAnEmptyRangeNegativeBoundsAndBadNumbers) {
  EXPECT_EQ(ErrorOf([] { ParseUrdf(WithLimit("revolute", "<limit lower=\"2\" upper=\"1\" effort=\"1\" velocity=\"1\"/>"), "r.urdf"); }),
            "r.urdf: joint 'j': <limit> lower 2 is above upper 1");
  EXPECT_NE(ErrorOf([] { ParseUrdf(WithLimit("revolute", "<limit lower=\"-1\" upper=\"1\" effort=\"-5\" velocity=\"1\"/>"), "r.urdf"); })
                .find("r.urdf: joint 'j': <limit> velocity and effort must be >= 0"),
            std::string::npos);
  const std::string bad = ErrorOf([] { ParseUrdf(WithLimit("revolute", "<limit lower=\"-1\" upper=\"1x\" effort=\"5\" velocity=\"1\"/>"), "r.urdf"); });
  EXPECT_EQ(bad.rfind("r.urdf: joint 'j': <limit> (line 5): attribute 'upper'", 0), 0u) << bad;  // before urdfdom reads it
  EXPECT_NE(bad.find("upper"), std::string::npos) << bad;
}

// --- bundled and shared files ---

std::string SourceDir() {
  const char* dir = std::getenv("INERTIAL_SOURCE_DIR");
  return dir == nullptr ? std::string() : std::string(dir);
}

TEST(UrdfModelFiles, ExampleLeg) {
  if (SourceDir().empty()) GTEST_SKIP() << "INERTIAL_SOURCE_DIR is not set (run through ctest)";
  const RobotModel leg = LoadUrdf(SourceDir() + "/examples/leg3.urdf");
  EXPECT_EQ(leg.dof_names, (std::vector<std::string>{"abad", "hip", "knee"}));
  EXPECT_EQ(leg.body_links, (std::vector<std::string>{"abad_link", "thigh", "shank"}));
  EXPECT_EQ(leg.root_link, "base");
  EXPECT_EQ(leg.BodyIndex("foot"), 2);
  EXPECT_NEAR(leg.tree.inertia(2).mass(), 0.45 + 0.06, 1e-15);
  EXPECT_EQ(leg.tree.joint(0).axis, Vector3::UnitX());
  EXPECT_EQ(leg.tree.joint(2).axis, Vector3::UnitY());
}

TEST(UrdfModelFiles, ExampleArm) {
  if (SourceDir().empty()) GTEST_SKIP() << "INERTIAL_SOURCE_DIR is not set (run through ctest)";
  const RobotModel arm = LoadUrdf(SourceDir() + "/examples/arm7.urdf");
  ASSERT_EQ(arm.tree.num_dofs(), 7);
  for (int i = 0; i < 7; ++i) EXPECT_EQ(arm.dof_names[i], "joint" + std::to_string(i + 1));
  EXPECT_EQ(arm.BodyIndex("tool0"), 6);
  EXPECT_EQ(arm.LinkInBody("tool0").p_AB, Vector3(0, 0, 0.045));
  double mass = 0;
  for (int i = 0; i < 7; ++i) mass += arm.tree.inertia(i).mass();
  EXPECT_NEAR(mass, 4.0 + 4.0 + 3.0 + 2.7 + 1.7 + 1.8 + 0.5, 1e-12);
}

// The KUKA LWR4+ file of the shared data: its joint box_lwr_base_joint has two <origin> elements.
TEST(UrdfModelFiles, KukaLwr4WithTwoOriginsLoadsLikeUrdfdom) {
  const std::string dir = SourceDir() + "/../shared/data/kuka_lwr4";
  if (SourceDir().empty() || !std::filesystem::exists(dir + "/kuka_lwr4.urdf")) {
    GTEST_SKIP() << "the shared KUKA LWR4+ data (" << dir << ") is not present";
  }
  const std::string path = dir + "/kuka_lwr4.urdf";
  const RobotModel kuka = LoadUrdf(path);
  ASSERT_EQ(kuka.tree.num_dofs(), 7);
  for (int i = 0; i < 7; ++i) EXPECT_EQ(kuka.dof_names[i], "lwr_" + std::to_string(i) + "_joint");
  EXPECT_EQ(kuka.root_link, "box");
  EXPECT_EQ(kuka.BodyIndex("lwr_base_link"), -1);
  // urdfdom takes the first <origin>.
  EXPECT_EQ(kuka.LinkInBody("lwr_base_link").p_AB, Vector3(-0.25, 0, 1));

  // Both origins are pure translations of a link fixed to the base: either one alone gives the same
  // dynamics.
  const std::string text = testing::ReadTextFile(path);
  const std::string first = "<origin rpy=\"0 0 0\" xyz=\"-0.25 0 1\"/>", second = "<origin rpy=\"0 0 0\" xyz=\"0 0 0\"/>";
  const std::size_t at_first = text.find(first), at_second = text.find(second, at_first);
  ASSERT_NE(at_first, std::string::npos);
  ASSERT_NE(at_second, std::string::npos);
  std::string only_first = text, only_second = text;
  only_first.erase(at_second, second.size());
  only_second.erase(at_first, first.size());
  const RobotModel a = ParseUrdf(only_first, "only_first");
  const RobotModel b = ParseUrdf(only_second, "only_second");
  EXPECT_EQ(b.LinkInBody("lwr_base_link").p_AB, Vector3::Zero());
  Rng rng(3);
  for (int k = 0; k < 10; ++k) {
    const Eigen::VectorXd q = rng.UniformVector<7>(-2, 2), qd = rng.UniformVector<7>(-1, 1), qdd = rng.UniformVector<7>(-3, 3);
    const Eigen::VectorXd tau = kuka.tree.InverseDynamics(q, qd, qdd);
    EXPECT_EQ(tau, a.tree.InverseDynamics(q, qd, qdd));
    EXPECT_LT(RelativeError(b.tree.InverseDynamics(q, qd, qdd), tau), 1e-13);
  }
}

}  // namespace
}  // namespace inertial
