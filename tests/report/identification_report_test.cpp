// Identification of the bundled robots (examples/leg3.urdf, examples/arm7.urdf) from simulated logs
// with known parameters: the project's forward-dynamics simulator tracks a Fourier excitation with
// the true robot (perturbed links, friction, rotors), the torques get Gaussian noise, and the fit
// must reach the noise floor on a fresh trajectory with every body physically consistent, where
// linear least squares on the same data gives impossible bodies.
#include <gtest/gtest.h>

#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>

#include "inertial/inertia/consistency.hpp"
#include "inertial/report/identification_report.hpp"
#include "simulated_robot.hpp"

namespace inertial {
namespace {

using testing::Example;
using testing::SimulatedLogs;
using testing::TrueParameters;

void ExpectIdentified(const RobotDynamics& model, const Eigen::VectorXd& x_true, double sigma) {
  const SimulatedLogs s = testing::SimulateLogs(model, x_true, sigma, 40.0, 7);
  const JointNormalEquations eq = AccumulateNormalEquations(model, s.train);
  const IdentificationRun run = RunIdentification(model, s.train, &s.test, JointIdentificationOptions());
  ASSERT_TRUE(run.fit.lm.converged()) << ToString(run.fit.lm.reason) << " after " << run.fit.lm.iterations;
  // The identifiable combinations: the fit predicts the noise-free torques of a trajectory it never
  // saw to a small fraction of the noise, and the noisy ones to the noise floor.
  const TorqueErrors clean = CompareTorques(PredictJointTorques(model, run.fit.x, s.test_clean), s.test_clean.tau);
  std::cerr << model.bodies().size() << " bodies, " << model.num_parameters() << " parameters: validation RMS "
            << run.fit_validation->total_rms << " N m (noise " << sigma << "), against noise-free torques "
            << clean.total_rms << ", prior " << run.prior_validation->total_rms << "; " << run.fit.lm.iterations
            << " iterations\n";
  EXPECT_LT(clean.total_rms, 0.25 * sigma);
  EXPECT_LT(run.fit_validation->total_rms, 1.05 * sigma);
  EXPECT_GT(run.prior_validation->total_rms, 3.0 * sigma);
  for (int e = 0; e < static_cast<int>(model.bodies().size()); ++e) {
    EXPECT_TRUE(CheckConsistency(model.BodyInertia(e, run.fit.x)).fully_consistent()) << model.bodies()[e].name;
  }
  // Linear least squares on pi (the minimum-norm solution of the rank-deficient problem).
  const Eigen::VectorXd w = eq.AtA.completeOrthogonalDecomposition().solve(eq.Atb);
  int impossible = 0;
  for (int b = 0; b < model.tree().num_bodies(); ++b) {
    impossible += !CheckConsistency(InertialParams::FromVector(w.segment<10>(10 * b))).fully_consistent();
  }
  std::cerr << "linear least squares: " << impossible << " of " << model.tree().num_bodies() << " bodies impossible\n";
  EXPECT_GT(impossible, 0);
}

TEST(RobotIdentification, Leg3WithRotorsAndFrictionFromASimulatedLog) {
  const RobotModel robot = LoadUrdf(Example("leg3.urdf"));
  const RobotDynamics model =
      MakeRobotDynamics(robot, ParseEffectList("viscous,coulomb:scale=0.05,rotor@abad:gear=6,rotor@hip:gear=6,rotor@knee:gear=9.33"));
  EXPECT_EQ(model.num_parameters(), 66);  // the "about 66": 6 bodies x 10 + 2 x 3 friction
  ExpectIdentified(model, TrueParameters(model, {0.2, 0.2, 0.2, 0.5, 0.5, 0.5}, 3), 0.3);
}

TEST(RobotIdentification, Arm7WithFrictionAndOffsetsFromASimulatedLog) {
  const RobotModel robot = LoadUrdf(Example("arm7.urdf"));
  const RobotDynamics model = MakeRobotDynamics(robot, ParseEffectList("viscous,coulomb:scale=0.05,offset"));
  ExpectIdentified(model, TrueParameters(model, {0.3, 0.3, 0.3, 0.3, 0.3, 0.3, 0.3, 0.8, 0.8, 0.8, 0.8, 0.8, 0.8, 0.8,
                                                 0.5, -0.5, 0.2, 0.1, -0.1, 0.05, 0.02}, 4),
                   0.5);
}

// The arm with friction and offsets has more identifiable combinations than the text lists (30):
// the text shows exactly the 30 whose std is largest relative to their value (ranked here from the
// JSON, which has them all) and says how many more --json holds; the JSON's values are k^T w at
// the fit and its stds the fit's (UncertaintyOfCombination), one per combination.
TEST(RobotIdentification, ArmTextListsTheLeastCertainBaseCombinations) {
  const RobotModel robot = LoadUrdf(Example("arm7.urdf"));
  const RobotDynamics model = MakeRobotDynamics(robot, ParseEffectList("viscous,offset"));
  const SimulatedLogs s = testing::SimulateLogs(model, TrueParameters(model, {0.5, 0.1}, 4), 0.3, 10.0, 9, 200);
  const IdentificationRun run = RunIdentification(model, s.train, nullptr, JointIdentificationOptions());
  ASSERT_TRUE(run.uncertainty.has_value()) << run.uncertainty_unavailable;
  const int R = run.identifiability.rank;
  ASSERT_GT(R, 30);
  const nlohmann::json j = IdentificationJson(model, run);
  ASSERT_EQ(static_cast<int>(j["base_combinations"].size()), R);
  const Eigen::VectorXd w = model.Coefficients(run.fit.x);
  std::vector<std::pair<double, std::string>> relative;
  for (int i = 0; i < R; ++i) {
    const nlohmann::json& c = j["base_combinations"][i];
    const BaseCombination& b = run.identifiability.base_combinations[i];
    EXPECT_EQ(c["text"].get<std::string>(), b.text);
    ASSERT_EQ(c["terms"].size(), b.terms.size());
    EXPECT_EQ(c["terms"][0][0].get<std::string>(), b.terms[0].first);
    const Eigen::VectorXd k = b.Vector(model.num_features());
    EXPECT_NEAR(c["value"].get<double>(), k.dot(w), 1e-12 * std::max(1.0, std::abs(k.dot(w)))) << b.text;
    const double sd = c["std"].get<double>();
    EXPECT_EQ(sd, UncertaintyOfCombination(run.uncertainty->coefficients, k).std) << b.text;
    relative.emplace_back(sd / std::abs(c["value"].get<double>()), b.text);
  }
  std::stable_sort(relative.begin(), relative.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  std::set<std::string> expected;
  for (int i = 0; i < 30; ++i) expected.insert(relative[i].second);

  const std::string text = IdentificationText(model, run);
  const std::string header = "Identifiable combinations (base parameters): " + std::to_string(R) + " of " +
                             std::to_string(model.num_features());
  const size_t at = text.find(header);
  ASSERT_NE(at, std::string::npos) << text;
  std::istringstream lines(text.substr(at));
  std::string line;
  std::getline(lines, line);
  EXPECT_NE(line.find("the 30 least certain"), std::string::npos) << line;
  std::set<std::string> shown;
  while (std::getline(lines, line) && line.rfind("  ", 0) == 0 && line.rfind("  ...", 0) != 0) {
    shown.insert(line.substr(2, line.find(" = ") - 2));
  }
  std::cerr << R << " base combinations of " << model.num_features() << " coefficients; the text shows the 30 with std / |value| from "
            << relative[29].first << " to " << relative[0].first << "\n";
  EXPECT_EQ(shown, expected);
  EXPECT_EQ(line, "  ... and " + std::to_string(R - 30) + " more (see --json)");
}

}  // namespace
}  // namespace inertial
