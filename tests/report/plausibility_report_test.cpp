#include "inertial/report/plausibility_report.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "inertial/formats/model_file.hpp"
#include "simulated_robot.hpp"
#include "formats/urdf_text.hpp"

namespace inertial {
namespace {

bool Contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

TEST(PlausibilityReport, WarningLinesByVerdict) {
  RegionPlausibility p;
  EXPECT_EQ(PlausibilityWarning("link2", p), "");
  p.on_edge = true;
  p.words = "held on the edge";
  EXPECT_EQ(PlausibilityWarning("link2", p), "Note: link2: held on the edge\n");
  p.plausible = false;
  p.words = "denser than steel";
  EXPECT_EQ(PlausibilityWarning("link2", p), "Warning: link2: denser than steel\n");
}

// The mass ratio is printed where the mass was judged against a drawing, not where the body is its
// own reference.
TEST(PlausibilityReport, MassRatioOnlyWhereCompared) {
  const RobotDynamics model = MakeRobotDynamics(LoadUrdf(testing::Example("arm7.urdf")), {});
  const EstimatedBody& body = model.bodies()[1];
  const RegionPlausibility compared = JudgeAgainstRegion(body.prior, body.prior, *body.region, true);
  const RegionPlausibility own = JudgeAgainstRegion(body.prior, body.prior, *body.region, false);
  EXPECT_TRUE(Contains(PlausibilityText(body, compared), "mass 1 x the URDF's"));
  EXPECT_FALSE(Contains(PlausibilityText(body, own), "the URDF's"));
  EXPECT_EQ(PlausibilityJson(body, compared)["mass_ratio"], 1.0);
  EXPECT_TRUE(PlausibilityJson(body, own)["mass_ratio"].is_null());
}

// validate's and check's section for a model file whose link2 is four times its recorded prior.
TEST(PlausibilityReport, ModelSectionNamesTheReferenceAndWarns) {
  const RobotModel robot = LoadUrdf(testing::Example("arm7.urdf"));
  const RobotDynamics model = MakeRobotDynamics(robot, {});
  Eigen::VectorXd x = Eigen::VectorXd::Zero(model.num_parameters());
  x[10] = std::log(2.0);  // link2's mass x 4
  const auto path = testing::TempUrdfPath("identified.urdf");
  WriteModelUrdf(testing::Example("arm7.urdf"), path.string(), robot, model, SnapshotAt(model, x), "a test");
  const RobotModel file = LoadUrdf(path.string());
  std::filesystem::remove(path);
  const RobotDynamics read = MakeRobotDynamics(file, {});
  const std::vector<JudgedBody> judged = JudgeModelBodies(file, read, Eigen::VectorXd::Zero(read.num_parameters()));
  const std::string text = ModelPlausibilityText(judged);
  EXPECT_TRUE(Contains(text, "Plausibility (links against the URDF priors the model file records, as the fit that "
                             "wrote it judged them)\n")) << text;
  EXPECT_TRUE(Contains(text, "  link2: NOT plausible: region from joints and prior, slack ")) << text;
  EXPECT_TRUE(Contains(text, "mass 4 x the URDF's")) << text;
  EXPECT_TRUE(Contains(text, "(against recorded prior)\n")) << text;
  EXPECT_TRUE(Contains(text, "\nWarning: link2: 16 kg is 4 times the URDF's 4 kg")) << text;
  EXPECT_FALSE(Contains(text, "Warning: link1")) << text;
  const nlohmann::json j = ModelPlausibilityJson(judged);
  EXPECT_FALSE(j["plausible"].get<bool>());
  ASSERT_EQ(j["bodies"].size(), 7u);
  EXPECT_EQ(j["bodies"][1]["name"], "link2");
  EXPECT_EQ(j["bodies"][1]["against"], "recorded prior");
  EXPECT_FALSE(j["bodies"][1]["plausible"].get<bool>());
  EXPECT_NEAR(j["bodies"][1]["mass_ratio"].get<double>(), 4.0, 1e-9);
  EXPECT_TRUE(j["bodies"][0]["plausible"].get<bool>());
  EXPECT_EQ(ModelPlausibilityText({}), "");
}

TEST(PlausibilityReport, TotalMassAgainstTheWeighedRobot) {
  const RobotDynamics model = MakeRobotDynamics(LoadUrdf(testing::Example("arm7.urdf")), {});
  const Eigen::VectorXd x = Eigen::VectorXd::Zero(model.num_parameters());  // 17.7 kg of links
  const TotalMassPlausibility well = JudgeTotalMass(model, x, {33.0, 2.0});
  EXPECT_TRUE(well.within);
  EXPECT_FALSE(well.bound_acts);
  EXPECT_NEAR(well.slack, 1.0 - 19.7 / 33.0, 1e-12);
  EXPECT_EQ(TotalMassText(well),
            "Total mass: 17.7 kg of links + 2 kg fixed to the base = 19.7 kg against the robot's 33 kg as weighed "
            "(--total-mass): within it, 40.3 % below\n");
  EXPECT_EQ(TotalMassWarning(well), "");
  const TotalMassPlausibility near = JudgeTotalMass(model, x, {18.5, 0.0});
  EXPECT_TRUE(near.bound_acts);
  EXPECT_TRUE(Contains(TotalMassText(near), "within it, 4.32 % below (within 5 % of it, where the bound acts on a fit)"));
  const TotalMassPlausibility heavy = JudgeTotalMass(model, x, {10.0, 0.0});
  EXPECT_FALSE(heavy.within);
  EXPECT_EQ(TotalMassText(heavy),
            "Total mass: 17.7 kg of links against the robot's 10 kg as weighed (--total-mass): NOT plausible: 17.7 kg "
            "is 1.77 times what the robot weighs\n");
  EXPECT_TRUE(Contains(TotalMassWarning(heavy), "Warning: the links weigh 17.7 kg, more than the 10 kg the robot weighs"));
  const nlohmann::json j = TotalMassJson(heavy);
  EXPECT_DOUBLE_EQ(j["total"].get<double>(), 17.7);
  EXPECT_FALSE(j["within"].get<bool>());
}

}  // namespace
}  // namespace inertial
