// The online estimator's estimate as text: before any sample it is the URDF's bodies (leg3: masses
// and COMs read off the file, the foot merged into the shank by hand), with standard deviations
// only for an estimator that keeps a covariance.
#include "inertial/report/online_estimate_text.hpp"

#include <gtest/gtest.h>

#include "inertial/formats/model_file.hpp"
#include "simulated_robot.hpp"

namespace inertial {
namespace {

OnlineJointEstimator Leg(EstimatorKind kind) {
  const RobotModel robot = LoadUrdf(testing::Example("leg3.urdf"));
  const RobotDynamics model = MakeRobotDynamics(robot, {});
  OnlineEstimatorOptions options;
  options.kind = kind;
  return OnlineJointEstimator(model, Eigen::VectorXd::Zero(model.num_parameters()), options);
}

TEST(OnlineEstimateText, WithoutACovarianceMassAndComPerBody) {
  // Shank and foot: (0.45 kg at z = -0.13 m, 0.06 kg at z = -0.34 m) -> 0.51 kg at -0.0789 / 0.51 m.
  // Each body is followed by its plausibility: the estimate is the prior itself (theta = 0), so it
  // is inside its region (joints and prior: the leg's URDF draws no shapes) at exactly the URDF's mass.
  const std::string text = OnlineEstimateText(Leg(EstimatorKind::kGradient));
  const std::string plausible = "    plausible: region from joints and prior, slack ";
  const std::string lines[] = {"final estimate:\n",
                               "  abad_link: mass 2 kg, COM [    0 0.055     0] m\n" + plausible,
                               "  thigh: mass 1.8 kg, COM [    0 0.016 -0.07] m\n" + plausible,
                               "  shank: mass 0.51 kg, COM [        0         0 -0.154706] m\n" + plausible};
  size_t at = 0;
  for (const std::string& line : lines) {
    at = text.find(line, at);
    ASSERT_NE(at, std::string::npos) << line << "\nin\n" << text;
  }
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 7) << text;
  // Every body at exactly its URDF's mass.
  int at_prior_mass = 0;
  const std::string ratio = "kg/m^3 over it, mass 1 x the URDF's\n";
  for (size_t p = text.find(ratio); p != std::string::npos; p = text.find(ratio, p + 1)) ++at_prior_mass;
  EXPECT_EQ(at_prior_mass, 3) << text;
  EXPECT_EQ(text.find("Warning"), std::string::npos) << text;
}

TEST(OnlineEstimateText, WithACovarianceEveryNumberHasItsStandardDeviation) {
  const std::string text = OnlineEstimateText(Leg(EstimatorKind::kEkf));
  EXPECT_EQ(text.rfind("final estimate (+- one standard deviation ", 0), 0u) << text;
  EXPECT_NE(text.find("):\n  abad_link: mass 2 +- "), std::string::npos) << text;
  EXPECT_NE(text.find("\n  thigh: mass 1.8 +- "), std::string::npos) << text;
  EXPECT_NE(text.find("\n  shank: mass 0.51 +- "), std::string::npos) << text;
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 7);  // 1 + 3 bodies x (estimate, plausibility)
  EXPECT_EQ(text.back(), '\n');
}

}  // namespace
}  // namespace inertial
