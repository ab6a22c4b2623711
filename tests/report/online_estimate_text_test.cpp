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
  EXPECT_EQ(OnlineEstimateText(Leg(EstimatorKind::kGradient)),
            "final estimate:\n"
            "  abad_link: mass 2 kg, COM [    0 0.055     0] m\n"
            "  thigh: mass 1.8 kg, COM [    0 0.016 -0.07] m\n"
            "  shank: mass 0.51 kg, COM [        0         0 -0.154706] m\n");
}

TEST(OnlineEstimateText, WithACovarianceEveryNumberHasItsStandardDeviation) {
  const std::string text = OnlineEstimateText(Leg(EstimatorKind::kEkf));
  EXPECT_EQ(text.rfind("final estimate (+- one standard deviation ", 0), 0u) << text;
  EXPECT_NE(text.find("):\n  abad_link: mass 2 +- "), std::string::npos) << text;
  EXPECT_NE(text.find("\n  thigh: mass 1.8 +- "), std::string::npos) << text;
  EXPECT_NE(text.find("\n  shank: mass 0.51 +- "), std::string::npos) << text;
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 4);
  EXPECT_EQ(text.back(), '\n');
}

}  // namespace
}  // namespace inertial
