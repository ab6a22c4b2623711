// The predictions file of a one-link pendulum whose torque is known in closed form: a link of 2 kg
// with its COM 0.5 m out along x, 0.03 kg m^2 about its COM's z axis (0.02, 0.025 about x, y), on
// a revolute joint about z with gravity -9.81 along y: tau = (0.03 + 2 * 0.5^2) qdd + 2 * 9.81 * 0.5 cos q.
#include "inertial/formats/torque_predictions.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <sstream>

#include "formats/urdf_text.hpp"
#include "inertial/formats/joint_csv.hpp"
#include "inertial/formats/model_file.hpp"

namespace inertial {
namespace {

using namespace testing;

RobotDynamics Pendulum() {
  const std::string xml =
      RobotXml("pendulum", LinkXml("base") +
                               LinkXml("arm", InertialXml(2, Vector3(0.5, 0, 0), Vector3::Zero(),
                                                          Vector3(0.02, 0.025, 0.03).asDiagonal())) +
                               JointXml("swing", "revolute", "base", "arm"));
  return MakeRobotDynamics(ParseUrdf(xml, "pendulum.urdf"), {}, Vector3(0, -9.81, 0));
}

TEST(TorquePredictions, HeaderNamesEveryJoint) {
  EXPECT_EQ(TorquePredictionHeader(Pendulum()), (std::vector<std::string>{"t", "tau_hat_swing"}));
}

TEST(TorquePredictions, ThePendulumsClosedFormTorques) {
  const RobotDynamics model = Pendulum();
  JointSamples data;
  data.joint_names = {"swing"};
  data.t = Eigen::VectorXd(3);
  data.t << 0.0, 0.5, 1.0;
  data.q = Eigen::MatrixXd(3, 1);
  data.q << 0.0, M_PI / 3, M_PI / 2;
  data.qd = Eigen::MatrixXd::Constant(3, 1, 0.7);
  data.qdd = Eigen::MatrixXd(3, 1);
  data.qdd << 1.0, -2.0, 0.0;
  data.tau = Eigen::MatrixXd::Zero(3, 1);
  const std::filesystem::path path = TempUrdfPath("predictions.csv");
  WriteTorquePredictions(path.string(), model, Eigen::VectorXd::Zero(model.num_parameters()), data);
  std::istringstream in(ReadTextFile(path));
  std::string line;
  ASSERT_TRUE(std::getline(in, line));
  EXPECT_EQ(line, "t,tau_hat_swing");
  for (int i = 0; i < 3; ++i) {
    ASSERT_TRUE(std::getline(in, line)) << "row " << i;
    char* end = nullptr;
    const double t = std::strtod(line.c_str(), &end);
    ASSERT_EQ(*end, ',') << line;
    const double tau = std::strtod(end + 1, nullptr);
    EXPECT_DOUBLE_EQ(t, data.t[i]);
    EXPECT_NEAR(tau, 0.53 * data.qdd(i, 0) + 9.81 * std::cos(data.q(i, 0)), 1e-12) << "row " << i;
  }
  EXPECT_FALSE(std::getline(in, line) && !line.empty());
  std::filesystem::remove(path);
}

TEST(TorquePredictions, AnUnwritablePathIsACsvError) {
  const RobotDynamics model = Pendulum();
  JointSamples data;
  data.joint_names = {"swing"};
  data.t = Eigen::VectorXd::Zero(1);
  data.q = data.qd = data.qdd = data.tau = Eigen::MatrixXd::Zero(1, 1);
  EXPECT_THROW(WriteTorquePredictions("/nonexistent/p.csv", model, Eigen::VectorXd::Zero(model.num_parameters()), data),
               CsvError);
}

}  // namespace
}  // namespace inertial
