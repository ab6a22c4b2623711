// A payload in the forms controllers load (payload_report.hpp), character by character against
// strings written out by hand for a hand-made payload: m = 2.5 kg, COM (0.01, -0.02, 0.05) m,
// inertia about the COM [[0.04, -0.001, 0.002], [-0.001, 0.05, 0.003], [0.002, 0.003, 0.06]] kg m^2
// (numbers whose shortest round-trip spelling is the plain decimal); the report's text and JSON
// carry the same strings, the standard deviations, and the held quantities' names; an online
// pick-up event gives the same strings for the same body, a put-down none.
#include "inertial/report/payload_report.hpp"

#include <gtest/gtest.h>

#include <limits>
#include <optional>
#include <string>

namespace inertial {
namespace {

PayloadValues HandMade() {
  PayloadValues p;
  p.mass = 2.5;
  p.com = Vector3(0.01, -0.02, 0.05);
  p.inertia_about_com << 0.04, -0.001, 0.002,  //
      -0.001, 0.05, 0.003,                     //
      0.002, 0.003, 0.06;
  return p;
}

TEST(PayloadReport, UrScriptByHand) {
  // set_target_payload(m, cog, inertia = [Ixx, Iyy, Izz, Ixy, Ixz, Iyz]).
  EXPECT_EQ(UrScriptPayload(HandMade()),
            "set_target_payload(2.5, [0.01, -0.02, 0.05], [0.04, 0.05, 0.06, -0.001, 0.002, 0.003])");
}

TEST(PayloadReport, FrankaSetLoadByHand) {
  // load_inertia column-major: (0,0) (1,0) (2,0), (0,1) (1,1) (2,1), (0,2) (1,2) (2,2).
  EXPECT_EQ(FrankaSetLoad(HandMade()),
            "robot.setLoad(2.5, {0.01, -0.02, 0.05}, {0.04, -0.001, 0.002, -0.001, 0.05, 0.003, 0.002, 0.003, 0.06});");
  // An asymmetric matrix shows the order is columns first (the function never sees one from a body).
  PayloadValues p = HandMade();
  p.inertia_about_com(1, 0) = -0.0015;
  EXPECT_EQ(FrankaSetLoad(p),
            "robot.setLoad(2.5, {0.01, -0.02, 0.05}, {0.04, -0.0015, 0.002, -0.001, 0.05, 0.003, 0.002, 0.003, 0.06});");
}

TEST(PayloadReport, UrdfLinkByHand) {
  EXPECT_EQ(UrdfPayloadLink(HandMade(), "tool0"),
            "<link name=\"payload\">\n"
            "  <inertial>\n"
            "    <origin xyz=\"0.01 -0.02 0.05\" rpy=\"0 0 0\"/>\n"
            "    <mass value=\"2.5\"/>\n"
            "    <inertia ixx=\"0.04\" ixy=\"-0.001\" ixz=\"0.002\" iyy=\"0.05\" iyz=\"0.003\" izz=\"0.06\"/>\n"
            "  </inertial>\n"
            "</link>\n"
            "<joint name=\"payload_joint\" type=\"fixed\">\n"
            "  <parent link=\"tool0\"/>\n"
            "  <child link=\"payload\"/>\n"
            "  <origin xyz=\"0 0 0\" rpy=\"0 0 0\"/>\n"
            "</joint>\n");
}

TEST(PayloadReport, NumbersRoundTrip) {
  // Not rounded: a fit's number comes back as the same double.
  PayloadValues p = HandMade();
  p.mass = 2.0001126414836423;
  p.com.x() = 1.0 / 3.0;
  EXPECT_EQ(UrScriptPayload(p).substr(0, 60), "set_target_payload(2.0001126414836423, [0.3333333333333333, ");
}

PayloadIdentification Identified() {
  const PayloadValues p = HandMade();
  PayloadIdentification r;
  r.link = "tool0";
  r.payload = InertialParams::FromMassComInertia(p.mass, p.com, p.inertia_about_com);
  r.uncertainty.mass = 0.004;
  r.uncertainty.com = Vector3(0.001, 0.002, 0.003);
  r.uncertainty.inertia_about_com << 0.01, 0.02, 0.03, 0.004, 0.005, std::numeric_limits<double>::infinity();
  r.held.inertia_about_com[0] = true;  // Ixx
  r.held.inertia_about_com[4] = true;  // Iyz
  r.num_samples = 1000;
  return r;
}

TEST(PayloadReport, JsonCarriesValuesStdsHeldAndTheControllerStrings) {
  const PayloadIdentification r = Identified();
  const nlohmann::json j = PayloadJson(r);
  EXPECT_EQ(j["link"], "tool0");
  EXPECT_NEAR(j["mass"].get<double>(), 2.5, 1e-15);
  EXPECT_EQ(j["mass_std"].get<double>(), 0.004);
  EXPECT_NEAR(j["com"][1].get<double>(), -0.02, 1e-15);
  EXPECT_EQ(j["com_std"][2].get<double>(), 0.003);
  EXPECT_NEAR(j["inertia_about_com"]["ixz"].get<double>(), 0.002, 1e-15);
  EXPECT_NEAR(j["inertia_about_com"]["iyz"].get<double>(), 0.003, 1e-15);
  // BodyUncertainty's order is Ixx Iyy Izz Ixy Iyz Ixz: iyz is its fifth, ixz its sixth.
  EXPECT_EQ(j["inertia_about_com_std"]["iyz"].get<double>(), 0.005);
  EXPECT_EQ(j["inertia_about_com_std"]["ixz"], "inf");
  EXPECT_EQ(j["held_by_prior"], (std::vector<std::string>{"Ixx", "Iyz"}));
  const PayloadValues p = PayloadValuesOf(r.payload);
  EXPECT_EQ(j["ur_script"], UrScriptPayload(p));
  EXPECT_EQ(j["franka"], FrankaSetLoad(p));
  EXPECT_EQ(j["urdf"], UrdfPayloadLink(p, "tool0"));
}

TEST(PayloadReport, TextNamesHeldQuantitiesAndCarriesTheControllerStrings) {
  const PayloadIdentification r = Identified();
  const std::string text = PayloadText(r);
  const PayloadValues p = PayloadValuesOf(r.payload);
  EXPECT_NE(text.find("payload on tool0"), std::string::npos) << text;
  EXPECT_NE(text.find("mass 2.5 +- 0.004 kg"), std::string::npos) << text;
  EXPECT_NE(text.find("held by the prior (the data barely determine them): Ixx, Iyz"), std::string::npos) << text;
  EXPECT_NE(text.find("\n  " + UrScriptPayload(p) + "\n"), std::string::npos) << text;
  EXPECT_NE(text.find("\n  " + FrankaSetLoad(p) + "\n"), std::string::npos) << text;
  EXPECT_NE(text.find("\n  <link name=\"payload\">\n    <inertial>\n"), std::string::npos) << text;
}

TEST(PayloadReport, AnOnlinePickUpEventInTheSameForm) {
  const PayloadValues p = HandMade();
  const InertialParams body = InertialParams::FromMassComInertia(p.mass, p.com, p.inertia_about_com);
  PayloadEvent pick;
  pick.link = "link7";
  pick.added_mass = body.mass();
  pick.added_pi = body.vector();
  const std::optional<PayloadValues> v = PayloadValuesOf(pick);
  ASSERT_TRUE(v.has_value());
  EXPECT_EQ(UrScriptPayload(*v), UrScriptPayload(PayloadValuesOf(body)));
  EXPECT_EQ(FrankaSetLoad(*v), FrankaSetLoad(PayloadValuesOf(body)));
  // A put-down removes a body: what the controller holds afterwards is not in the event.
  PayloadEvent place = pick;
  place.added_mass = -body.mass();
  place.added_pi = -body.vector();
  EXPECT_FALSE(PayloadValuesOf(place).has_value());
  // An event without a fit (the arm did not move enough): NaN quantities.
  PayloadEvent unknown;
  unknown.added_mass = std::numeric_limits<double>::quiet_NaN();
  unknown.added_pi.setConstant(std::numeric_limits<double>::quiet_NaN());
  EXPECT_FALSE(PayloadValuesOf(unknown).has_value());
}

}  // namespace
}  // namespace inertial
