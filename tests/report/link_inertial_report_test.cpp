// The text and JSON of `inertial check` for checks written out by hand (nothing is checked here):
// every kind of link, the repair line, and the totals.
#include "inertial/report/link_inertial_report.hpp"

#include <gtest/gtest.h>

namespace inertial {
namespace {

LinkInertialCheck Present(const std::string& name, bool consistent) {
  LinkInertialCheck l;
  l.link = name;
  l.used_by_dynamics = true;
  l.kind = LinkInertialKind::kPresent;
  ConsistencyReport& r = l.consistency;
  r.finite = r.mass_positive = r.inertia_positive_definite_com = r.pseudo_inertia_positive_definite = true;
  r.triangle_inequalities = consistent;
  r.mass = 2;
  r.min_inertia_eigenvalue_com = 0.123456;
  r.min_triangle_margin = consistent ? 0.5 : -0.25;
  r.min_pseudo_inertia_eigenvalue = 1e-5;
  if (!consistent) r.reason = "too thin";
  return l;
}

UrdfInertialCheck Example() {
  UrdfInertialCheck c;
  c.path = "r.urdf";
  c.robot = "r";
  c.moving_joints = 2;
  LinkInertialCheck base;
  base.link = "base";
  LinkInertialCheck frame;
  frame.link = "frame";
  frame.used_by_dynamics = true;
  frame.kind = LinkInertialKind::kZero;
  LinkInertialCheck fixed = Present("bad", false);
  fixed.repaired = InertialParams::FromMassComInertia(2, Vector3(1, 0, 0), Vector3(0.1, 0.2, 0.25).asDiagonal());
  LinkInertialCheck worse = Present("worse", false);
  worse.unrepairable = "no mass";
  c.links = {base, Present("arm", true), frame, fixed, worse};
  return c;
}

TEST(LinkInertialReport, TextOfEveryKindOfLink) {
  const std::string margins =
      "    mass 2 kg; at the COM: min inertia eigenvalue 0.1235 kg m^2, min triangle margin ";
  const std::string expected =
      "r.urdf: robot 'r', 5 links, 2 moving joints\n"
      "  base: no <inertial> (fixed to the base: not used by the dynamics)\n"
      "  arm: consistent\n" + margins + "0.5 kg m^2; min pseudo-inertia eigenvalue 1e-05\n"
      "  frame: zero <inertial> (massless frame)\n"
      "  bad: IMPOSSIBLE\n" + margins + "-0.25 kg m^2; min pseudo-inertia eigenvalue 1e-05\n"
      "    too thin\n"
      "    nearest consistent (same mass and COM): inertia about the COM [Ixx Iyy Izz Ixy Iyz Ixz] = [0.1 0.2 0.25 0 0 0] kg m^2\n"
      "  worse: IMPOSSIBLE\n" + margins + "-0.25 kg m^2; min pseudo-inertia eigenvalue 1e-05\n"
      "    too thin\n"
      "    cannot be repaired: no mass\n"
      "3 inertials checked: 2 impossible\n";
  EXPECT_EQ(LinkInertialText(Example()), expected);
}

TEST(LinkInertialReport, TheRepairLineAndTheAllConsistentTotal) {
  UrdfInertialCheck c = Example();
  c.links.resize(2);
  UrdfRepair repair;
  repair.path = "out.urdf";
  const std::string text = LinkInertialText(c, &repair);
  EXPECT_NE(text.find("\n1 inertials checked: all physically consistent\n"
                      "wrote out.urdf: 0 links repaired; every inertial in it is physically consistent\n"),
            std::string::npos)
      << text;
  repair.repaired = 3;
  repair.still_impossible = 2;
  EXPECT_NE(LinkInertialText(c, &repair).find("wrote out.urdf: 3 links repaired; 2 still impossible (mass <= 0)\n"),
            std::string::npos);
}

TEST(LinkInertialReport, Json) {
  const nlohmann::json j = LinkInertialJson(Example());
  EXPECT_EQ(j["model"], "r.urdf");
  EXPECT_EQ(j["checked"], 3);
  EXPECT_EQ(j["impossible"], 2);
  EXPECT_EQ(j["all_consistent"], false);
  EXPECT_FALSE(j.contains("repaired"));
  ASSERT_EQ(j["links"].size(), 5u);
  EXPECT_EQ(j["links"][0], nlohmann::json::parse(
                               R"({"link": "base", "used_by_dynamics": false, "inertial": "absent", "physically_consistent": null})"));
  EXPECT_EQ(j["links"][2]["inertial"], "zero");
  EXPECT_EQ(j["links"][1]["physically_consistent"], true);
  EXPECT_EQ(j["links"][1]["min_triangle_margin"], 0.5);
  EXPECT_FALSE(j["links"][1].contains("reason"));
  EXPECT_EQ(j["links"][3]["reason"], "too thin");
  const std::vector<double> repaired = j["links"][3]["repaired_inertia_about_com"];
  ASSERT_EQ(repaired.size(), 6u);
  EXPECT_NEAR(repaired[0], 0.1, 1e-14);
  EXPECT_NEAR(repaired[2], 0.25, 1e-14);
  EXPECT_NEAR(repaired[5], 0.0, 1e-14);
  EXPECT_EQ(j["links"][4]["repair"], "no mass");
  UrdfRepair repair;
  repair.repaired = 1;
  EXPECT_EQ(LinkInertialJson(Example(), &repair)["repaired"], 1);
}

}  // namespace
}  // namespace inertial
