#include "inertial/formats/model_plausibility.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "inertial/formats/model_file.hpp"
#include "inertial/inertia/closed_form_bodies.hpp"
#include "simulated_robot.hpp"
#include "urdf_text.hpp"

namespace inertial {
namespace {

// arm7.urdf with link2's mass (4 kg) written as `mass` and its inertia about the COM multiplied by
// `inertia_scale` (1: a mass typed wrong, the inertia left as drawn).
std::string Arm7WithLink2(double mass, double inertia_scale) {
  std::string text = testing::ReadTextFile(testing::Example("arm7.urdf"));
  const std::size_t link = text.find("<link name=\"link2\">");
  const std::size_t at = text.find("<mass value=\"4.0\"/>", link);
  EXPECT_NE(at, std::string::npos);
  text.replace(at, std::string("<mass value=\"4.0\"/>").size(), "<mass value=\"" + testing::Num(mass) + "\"/>");
  if (inertia_scale != 1.0) {
    const std::size_t start = text.find("<inertia ", at), end = text.find("/>", start);
    std::string tag = text.substr(start, end - start);
    for (const char* key : {"ixx=\"", "iyy=\"", "izz=\"", "ixy=\"", "ixz=\"", "iyz=\""}) {
      const std::size_t k = tag.find(key);
      if (k == std::string::npos) continue;
      const std::size_t v = k + std::string(key).size(), q = tag.find('"', v);
      tag.replace(v, q - v, testing::Num(std::stod(tag.substr(v, q - v)) * inertia_scale));
    }
    text.replace(start, end - start, tag);
  }
  return text;
}

std::vector<JudgedBody> Judge(const RobotModel& robot) {
  const RobotDynamics model = MakeRobotDynamics(robot, robot.DeclaredEffects());
  return JudgeModelBodies(robot, model, Eigen::VectorXd::Zero(model.num_parameters()));
}

// The bundled arm as drawn: every link plausible, each its own reference (its mass not compared).
TEST(ModelPlausibility, TheBundledArmIsPlausible) {
  const std::vector<JudgedBody> judged = Judge(LoadUrdf(testing::Example("arm7.urdf")));
  ASSERT_EQ(judged.size(), 7u);
  for (const JudgedBody& j : judged) {
    EXPECT_TRUE(j.plausibility.plausible) << j.name << ": " << j.plausibility.words;
    EXPECT_FALSE(j.plausibility.mass_compared);
    EXPECT_FALSE(j.against_recorded_prior);
    EXPECT_STREQ(ReferenceName(j), "itself");
  }
}

// A 196 kg upper arm on an arm whose other links weigh 13.7 kg: denser than steel over its segment
// region, whether the mass alone was typed wrong (its radius shrinks 7 times) or the inertia scaled with it.
TEST(ModelPlausibility, AHundredAndNinetySixKilogramUpperArmIsNot) {
  for (double scale : {1.0, 49.0}) {
    const std::vector<JudgedBody> judged = Judge(ParseUrdf(Arm7WithLink2(196.0, scale), "<arm7 196 kg>"));
    ASSERT_EQ(judged[1].name, "link2");
    const RegionPlausibility& p = judged[1].plausibility;
    EXPECT_FALSE(p.plausible) << scale;
    EXPECT_GT(p.density, kMaxRegionDensity) << scale;  // measured: 4.7e5 and 9.6e3 kg/m^3
    EXPECT_NE(p.words.find("denser than steel"), std::string::npos) << p.words;
    RecordProperty("density_" + std::to_string(static_cast<int>(scale)), std::to_string(p.density));
    for (int e : {0, 2, 3, 4, 5, 6}) EXPECT_TRUE(judged[static_cast<size_t>(e)].plausibility.plausible) << e;
  }
}

// A link with a collision box: its inertia is judged against the box alone (with the shapes' 10 %
// margin), not against a region that also holds the inertia; a COM beside the box is outside it.
TEST(ModelPlausibility, ADrawingIsJudgedAgainstItsCollisionShapes) {
  using namespace testing;
  const auto arm = [](const Vector3& com) {
    const std::string box = "<collision><origin xyz=\"0 0 0.2\" rpy=\"0 0 0\"/><geometry><box size=\"0.1 0.1 0.4\"/>"
                            "</geometry></collision>";
    const Matrix3 I = SolidBox(2.0, 0.1, 0.1, 0.4).rotational_inertia_about_com();
    return RobotXml("boxed", LinkXml("base") + LinkXml("upper", InertialXml(2.0, com, Vector3::Zero(), I) + box) +
                                 JointXml("shoulder", "revolute", "base", "upper"));
  };
  const std::vector<JudgedBody> inside = Judge(ParseUrdf(arm(Vector3(0, 0, 0.2)), "<inside>"));
  ASSERT_EQ(inside.size(), 1u);
  EXPECT_EQ(inside[0].reference.region->source, RegionSource::kShape);
  EXPECT_TRUE(inside[0].plausibility.plausible) << inside[0].plausibility.words;
  // A solid box in its corners' ellipsoid (semi-axes sqrt(3) times the half sizes) grown 10 %: the
  // mean normalized squared distance is 3 (h^2 / 3) / (3 h^2 1.21) = 1 / 3.63.
  EXPECT_NEAR(inside[0].plausibility.slack, 1.0 - 1.0 / 3.63, 0.01);
  const std::vector<JudgedBody> beside = Judge(ParseUrdf(arm(Vector3(0, 0.3, 0.2)), "<beside>"));
  EXPECT_FALSE(beside[0].plausibility.plausible);
  EXPECT_LT(beside[0].plausibility.slack, 0.0);
  EXPECT_NE(beside[0].plausibility.words.find("outside its region (drawn geometry)"), std::string::npos)
      << beside[0].plausibility.words;
}

// A model file written from a fit whose link2 weighs four times its URDF's: read back, link2 is
// judged against the prior the file records, with the very verdict and numbers of the fit's own
// judgement (JudgeEstimatedBody), so validate and check call it implausible as identify did.
TEST(ModelPlausibility, AModelFileIsJudgedAgainstItsRecordedPriors) {
  const RobotModel robot = LoadUrdf(testing::Example("arm7.urdf"));
  const RobotDynamics model = MakeRobotDynamics(robot, {});
  Eigen::VectorXd x = Eigen::VectorXd::Zero(model.num_parameters());
  x[10] = 0.5 * std::log(4.0);  // link2's mass x 4
  x[17] = 0.02;                 // and its COM moved
  const auto path = testing::TempUrdfPath("identified.urdf");
  WriteModelUrdf(testing::Example("arm7.urdf"), path.string(), robot, model, SnapshotAt(model, x), "a test");
  const RobotModel file = LoadUrdf(path.string());
  ASSERT_EQ(file.recorded_priors.size(), 7u);
  EXPECT_LT((file.recorded_priors.at("link2").vector() - robot.tree.inertia(1).vector()).norm(), 1e-12);
  const std::vector<JudgedBody> judged = Judge(file);
  const std::optional<RegionPlausibility> fit = JudgeEstimatedBody(model.bodies()[1], x.segment<10>(10));
  ASSERT_TRUE(fit.has_value());
  const JudgedBody& link2 = judged[1];
  EXPECT_TRUE(link2.against_recorded_prior);
  EXPECT_FALSE(link2.plausibility.plausible);
  EXPECT_TRUE(link2.plausibility.mass_compared);
  EXPECT_NEAR(link2.plausibility.mass_ratio, 4.0, 1e-9);
  EXPECT_NEAR(link2.plausibility.slack, fit->slack, 1e-9);
  EXPECT_NEAR(link2.plausibility.density, fit->density, 1e-9 * fit->density);
  EXPECT_EQ(link2.plausibility.words, fit->words);
  EXPECT_EQ(link2.reference.region->source, model.bodies()[1].region->source);
  for (int e : {0, 2, 3, 4, 5, 6}) EXPECT_TRUE(judged[static_cast<size_t>(e)].plausibility.plausible) << e;

  // Written again from the file's model, the file keeps the first drawing (not its own values) as priors.
  const RobotDynamics again = MakeRobotDynamics(file, {});
  const auto second = testing::TempUrdfPath("again.urdf");
  WriteModelUrdf(path.string(), second.string(), file, again, SnapshotAt(again, Eigen::VectorXd::Zero(again.num_parameters())),
                 "a test");
  const RobotModel kept = LoadUrdf(second.string());
  EXPECT_LT((kept.recorded_priors.at("link2").vector() - robot.tree.inertia(1).vector()).norm(), 1e-12);
  EXPECT_FALSE(Judge(kept)[1].plausibility.plausible);
  std::filesystem::remove(path);
  std::filesystem::remove(second);
}

TEST(ModelPlausibility, MassFixedToTheBase) {
  using namespace testing;
  const Matrix3 I = Vector3(0.01, 0.01, 0.01).asDiagonal();
  const std::string text =
      RobotXml("based", LinkXml("base", InertialXml(5.0, Vector3::Zero(), Vector3::Zero(), I)) +
                            LinkXml("plate", InertialXml(1.5, Vector3::Zero(), Vector3::Zero(), I)) + LinkXml("marker") +
                            LinkXml("upper", InertialXml(2.0, Vector3(0, 0, 0.1), Vector3::Zero(), I)) +
                            JointXml("bolted", "fixed", "base", "plate") + JointXml("mark", "fixed", "base", "marker") +
                            JointXml("shoulder", "revolute", "plate", "upper"));
  const RobotModel robot = ParseUrdf(text, "<based>");
  EXPECT_DOUBLE_EQ(MassFixedToBase(robot), 6.5);
  EXPECT_EQ(LinksFixedToBase(robot), "base (5 kg), plate (1.5 kg)");
  EXPECT_EQ(MassFixedToBase(LoadUrdf(Example("arm7.urdf"))), 0.0);
  EXPECT_EQ(LinksFixedToBase(LoadUrdf(Example("arm7.urdf"))), "none");
}

}  // namespace
}  // namespace inertial
