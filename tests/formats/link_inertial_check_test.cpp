// CheckLinkInertials and WriteRepairedUrdf on a URDF written here with one link of each kind: a
// consistent box, a link thinner than a plate (Izz > Ixx + Iyy at the COM: triangle margin
// 0.01 + 0.012 - 0.05 = -0.028 kg m^2), a negative mass (no repair), a zero <inertial>, none.
#include "inertial/formats/link_inertial_check.hpp"

#include <gtest/gtest.h>

#include <filesystem>

#include "formats/urdf_text.hpp"

namespace inertial {
namespace {

using namespace testing;

std::string ArmXml() {
  const Matrix3 good = Vector3(0.02, 0.03, 0.025).asDiagonal();
  const Matrix3 thin = Vector3(0.01, 0.012, 0.05).asDiagonal();
  const Matrix3 any = Vector3(0.01, 0.01, 0.01).asDiagonal();
  return RobotXml("arm", LinkXml("base") + LinkXml("upper", InertialXml(1.5, Vector3(0, 0, 0.1), Vector3::Zero(), good)) +
                             LinkXml("fore", InertialXml(0.8, Vector3(0.1, 0.02, 0), Vector3(0.3, 0, 0.2), thin)) +
                             LinkXml("hand", InertialXml(-0.5, Vector3::Zero(), Vector3::Zero(), any)) +
                             LinkXml("tool", InertialXml(0, Vector3::Zero(), Vector3::Zero(), Matrix3::Zero())) +
                             LinkXml("marker") + JointXml("shoulder", "revolute", "base", "upper") +
                             JointXml("elbow", "revolute", "upper", "fore", Vector3(0, 0, 0.3)) +
                             JointXml("wrist", "revolute", "fore", "hand", Vector3(0.3, 0, 0)) +
                             JointXml("flange", "fixed", "hand", "tool") + JointXml("mount", "fixed", "base", "marker"));
}

const LinkInertialCheck& Link(const UrdfInertialCheck& check, const std::string& name) {
  for (const LinkInertialCheck& l : check.links) {
    if (l.link == name) return l;
  }
  throw std::runtime_error("no link " + name);
}

TEST(LinkInertialCheck, EveryKindOfLink) {
  UrdfLoadOptions load;
  load.require_consistent_inertials = false;
  const UrdfInertialCheck check = CheckLinkInertials("arm.urdf", ParseUrdf(ArmXml(), "arm.urdf", load));
  EXPECT_EQ(check.path, "arm.urdf");
  EXPECT_EQ(check.robot, "arm");
  EXPECT_EQ(check.moving_joints, 3);
  ASSERT_EQ(check.links.size(), 6u);
  EXPECT_EQ(check.checked(), 3);
  EXPECT_EQ(check.impossible(), 2);

  EXPECT_EQ(Link(check, "base").kind, LinkInertialKind::kAbsent);
  EXPECT_FALSE(Link(check, "base").used_by_dynamics);
  EXPECT_EQ(Link(check, "marker").kind, LinkInertialKind::kAbsent);
  EXPECT_FALSE(Link(check, "marker").used_by_dynamics);
  EXPECT_EQ(Link(check, "tool").kind, LinkInertialKind::kZero);
  EXPECT_TRUE(Link(check, "tool").used_by_dynamics);  // merged into the hand

  const LinkInertialCheck& upper = Link(check, "upper");
  EXPECT_FALSE(upper.impossible());
  EXPECT_NEAR(upper.consistency.min_triangle_margin, 0.02 + 0.025 - 0.03, 1e-12);
  EXPECT_NEAR(upper.consistency.min_inertia_eigenvalue_com, 0.02, 1e-12);

  const LinkInertialCheck& fore = Link(check, "fore");
  EXPECT_TRUE(fore.impossible());
  EXPECT_NEAR(fore.consistency.min_triangle_margin, -0.028, 1e-12);
  ASSERT_TRUE(fore.repaired.has_value());
  EXPECT_TRUE(fore.unrepairable.empty());
  EXPECT_NEAR(fore.repaired->mass(), 0.8, 1e-12);
  EXPECT_TRUE(fore.repaired->com().isApprox(Vector3(0.1, 0.02, 0), 1e-12)) << fore.repaired->com().transpose();
  EXPECT_TRUE(CheckConsistency(*fore.repaired).fully_consistent());

  const LinkInertialCheck& hand = Link(check, "hand");
  EXPECT_TRUE(hand.impossible());
  EXPECT_NEAR(hand.consistency.mass, -0.5, 1e-15);
  EXPECT_FALSE(hand.repaired.has_value());
  EXPECT_FALSE(hand.unrepairable.empty());

  const std::map<std::string, InertialParams> repairs = check.Repairs();
  ASSERT_EQ(repairs.size(), 1u);
  EXPECT_EQ(repairs.begin()->first, "fore");
}

TEST(LinkInertialCheck, TheRepairedCopyIsReadBackAndCounted) {
  const std::filesystem::path in = TempUrdfPath("arm.urdf"), out = TempUrdfPath("fixed.urdf");
  WriteTextFile(in, ArmXml());
  const UrdfInertialCheck check = CheckUrdfInertials(in.string());
  const UrdfRepair repair = WriteRepairedUrdf(check, out.string());
  EXPECT_EQ(repair.path, out.string());
  EXPECT_EQ(repair.repaired, 1);
  EXPECT_EQ(repair.still_impossible, 1);  // the negative mass
  const UrdfInertialCheck again = CheckUrdfInertials(out.string());
  EXPECT_FALSE(Link(again, "fore").impossible());
  EXPECT_NEAR(Link(again, "fore").consistency.mass, 0.8, 1e-12);
  EXPECT_TRUE(Link(again, "hand").impossible());
  std::filesystem::remove(in);
  std::filesystem::remove(out);
}

TEST(LinkInertialCheck, AMissingFileIsAUrdfError) {
  EXPECT_THROW(CheckUrdfInertials("/nonexistent/robot.urdf"), UrdfError);
}

}  // namespace
}  // namespace inertial
