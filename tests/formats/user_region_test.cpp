#include "inertial/formats/user_region.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "inertial/formats/model_file.hpp"
#include "inertial/formats/number_parsing.hpp"
#include "inertial/inertia/closed_form_bodies.hpp"
#include "inertial/model/rotation_from_rpy.hpp"
#include "simulated_robot.hpp"
#include "urdf_text.hpp"

namespace inertial {
namespace {

// The message of the std::invalid_argument `f` throws (empty if none).
template <typename F>
std::string ErrorOf(F f) {
  try {
    f();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(UserRegion, ParsesCentreSemiAxesAndRpy) {
  const UserRegion r = ParseUserRegion("link2=0.01,0.06,0.04,0.1,0.2,0.15:rpy=0.5,0,-1");
  EXPECT_EQ(r.target, "link2");
  EXPECT_EQ(r.center, Vector3(0.01, 0.06, 0.04));
  EXPECT_EQ(r.semi_axes, Vector3(0.1, 0.2, 0.15));
  EXPECT_EQ(r.rpy, Vector3(0.5, 0, -1));
  const UserRegion plain = ParseUserRegion("payload@tool0=0,0,0.05,0.1,0.1,0.1");
  EXPECT_EQ(plain.target, "payload@tool0");
  EXPECT_EQ(plain.rpy, Vector3::Zero());
}

TEST(UserRegion, RefusesBadTextSayingWhatIsWrong) {
  EXPECT_NE(ErrorOf([] { ParseUserRegion("link2"); }).find("expected LINK=cx,cy,cz,a,b,c"), std::string::npos);
  EXPECT_NE(ErrorOf([] { ParseUserRegion("=0,0,0,1,1,1"); }).find("no link"), std::string::npos);
  EXPECT_NE(ErrorOf([] { ParseUserRegion("link2=0,0,0,1,1"); }).find("5 numbers given, 6 expected"), std::string::npos);
  EXPECT_NE(ErrorOf([] { ParseUserRegion("link2=0,0,0,1,0,1"); }).find("semi-axis 2 is 0"), std::string::npos);
  EXPECT_NE(ErrorOf([] { ParseUserRegion("link2=0,0,0,1,1,-0.1"); }).find("semi-axis 3 is -0.1"), std::string::npos);
  EXPECT_NE(ErrorOf([] { ParseUserRegion("link2=0,0,0,1,1,1:rot=0,0,0"); }).find("unknown part 'rot=0,0,0'"),
            std::string::npos);
  EXPECT_NE(ErrorOf([] { ParseUserRegion("link2=0,0,0,1,1,1:rpy=0,0"); }).find("rpy: 2 numbers given, 3 expected"),
            std::string::npos);
  EXPECT_NE(ErrorOf([] { ParseUserRegion("link2=0,0,0,1,1,1:rpy=0,0,0:rpy=0,0,0"); }).find("twice"), std::string::npos);
  EXPECT_NE(ErrorOf([] { ParseUserRegion("link2=0,0,0,1200,80,80"); }).find("in metres"), std::string::npos);
  // Not finite or not a number: InvalidNumber, naming the option and the link.
  try {
    ParseUserRegion("link2=0,0,0,nan,1,1");
    ADD_FAILURE() << "no error";
  } catch (const InvalidNumber& e) {
    EXPECT_NE(std::string(e.what()).find("--region link2"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("not finite"), std::string::npos) << e.what();
  }
  EXPECT_THROW(ParseUserRegion("link2=0,0,0,inf,1,1"), InvalidNumber);
  EXPECT_THROW(ParseUserRegion("link2=0,0,0,1,1,1:rpy=0,x,0"), InvalidNumber);
}

class UserRegionOnArm : public ::testing::Test {
 protected:
  RobotModel robot = LoadUrdf(testing::Example("arm7.urdf"));
  RobotDynamics model = MakeRobotDynamics(robot, ParseEffectList("payload@tool0:mass=1"));
};

// A region given in a link's frame lands in its body's frame, axis-aligned or turned by rpy, with
// the automatic regions' mass bound (steel over its volume).
TEST_F(UserRegionOnArm, PlacesTheRegionInItsBodysFrame) {
  const UserRegion given = ParseUserRegion("link2=0,0.06,0.04,0.12,0.2,0.12:rpy=0.3,0,0");
  const PlacedUserRegion placed = PlaceUserRegion(robot, model, given);
  EXPECT_EQ(placed.body, 1);
  EXPECT_EQ(placed.region.source, RegionSource::kUser);
  EXPECT_NEAR(placed.region.ellipsoid.Volume(), 4.0 / 3.0 * M_PI * 0.12 * 0.2 * 0.12, 1e-12);
  EXPECT_NEAR(placed.region.max_mass, kMaxRegionDensity * placed.region.ellipsoid.Volume(), 1e-9);
  // The second semi-axis runs along y turned 0.3 rad about x.
  const Vector3 along = RotationFromRpy(Vector3(0.3, 0, 0)) * Vector3::UnitY();
  EXPECT_TRUE(placed.region.ellipsoid.Contains(Vector3(0, 0.06, 0.04) + 0.199 * along));
  EXPECT_FALSE(placed.region.ellipsoid.Contains(Vector3(0, 0.06, 0.04) + 0.201 * along));
  EXPECT_GT(placed.region.ellipsoid.Slack(model.bodies()[1].prior), 0.0);

  // tool0 is fixed to link7 0.045 m along its z: a region about tool0's origin is about that point
  // of link7's body.
  const PlacedUserRegion at_tool = PlaceUserRegion(robot, model, ParseUserRegion("tool0=0,0,-0.045,0.1,0.1,0.1"));
  EXPECT_EQ(at_tool.body, 6);
  EXPECT_LT((at_tool.region.ellipsoid.center - Vector3::Zero()).norm(), 1e-12);
  // A payload's region, in its link's frame.
  const PlacedUserRegion payload = PlaceUserRegion(robot, model, ParseUserRegion("payload@tool0=0,0,0,0.2,0.2,0.2"));
  EXPECT_EQ(model.bodies()[static_cast<size_t>(payload.body)].name, "payload@tool0");
  EXPECT_LT((payload.region.ellipsoid.center - Vector3(0, 0, 0.045)).norm(), 1e-12);
}

TEST_F(UserRegionOnArm, RefusesRegionsNoBodyCanTake) {
  const auto place = [&](const std::string& text) {
    return ErrorOf([&] { PlaceUserRegion(robot, model, ParseUserRegion(text)); });
  };
  const std::string unknown = place("link9=0,0,0,1,1,1");
  EXPECT_NE(unknown.find("no link 'link9'"), std::string::npos) << unknown;
  EXPECT_NE(unknown.find("link1, link2, link3"), std::string::npos) << unknown;
  EXPECT_NE(place("base_link=0,0,0,1,1,1").find("fixed to the base"), std::string::npos);
  EXPECT_NE(place("payload@link3=0,0,0,1,1,1").find("no payload@link3"), std::string::npos);
  EXPECT_NE(place("rotor@joint1=0,0,0,1,1,1").find("rotor has no region"), std::string::npos);
  // A ball of 5 cm two metres away does not hold link2's prior.
  const std::string far = place("link2=2,0,0,0.05,0.05,0.05");
  EXPECT_NE(far.find("does not hold link2's prior"), std::string::npos) << far;
  EXPECT_NE(far.find("slack in the region is -"), std::string::npos) << far;
  // Without require_body, a payload the model lacks is skipped, not an error.
  EXPECT_EQ(PlaceUserRegion(robot, model, ParseUserRegion("payload@link3=0,0,0,1,1,1"), false).body, -1);
}

TEST_F(UserRegionOnArm, ApplyReplacesTheAutomaticRegionOncePerBody) {
  ApplyUserRegions(robot, {ParseUserRegion("link2=0,0.06,0.04,0.12,0.2,0.12")}, &model);
  ASSERT_TRUE(model.bodies()[1].region.has_value());
  EXPECT_EQ(model.bodies()[1].region->source, RegionSource::kUser);
  EXPECT_NE(model.bodies()[0].region->source, RegionSource::kUser);
  const std::string twice = ErrorOf([&] {
    ApplyUserRegions(robot, {ParseUserRegion("link7=0,0,0,0.1,0.1,0.1"), ParseUserRegion("tool0=0,0,0,0.1,0.1,0.1")},
                     &model);
  });
  EXPECT_NE(twice.find("tool0=0,0,0,0.1,0.1,0.1: link7 already has a region (link7=0,0,0,0.1,0.1,0.1)"),
            std::string::npos)
      << twice;
}

// A region holding a dense link's prior in shape but too small for its mass: 100 kg in a ball of
// 10 cm (23,900 kg/m^3) given a ball of 11 cm, which steel fills with 43.8 kg.
TEST(UserRegion, RefusesARegionTooSmallForThePriorsMass) {
  const std::string body = testing::LinkXml("base") +
                           testing::LinkXml("heavy", testing::InertialXml(100, Vector3::Zero(), Vector3::Zero(),
                                                                          SolidSphere(100, 0.1).rotational_inertia_about_com())) +
                           testing::JointXml("j", "revolute", "base", "heavy");
  const RobotModel robot = ParseUrdf(testing::RobotXml("dense", body), "<dense>");
  const RobotDynamics model = MakeRobotDynamics(robot, {});
  const std::string error = ErrorOf([&] { PlaceUserRegion(robot, model, ParseUserRegion("heavy=0,0,0,0.11,0.11,0.11")); });
  EXPECT_NE(error.find("too small for heavy's prior mass of 100 kg (at most 43.77 kg"), std::string::npos) << error;
}

}  // namespace
}  // namespace inertial
