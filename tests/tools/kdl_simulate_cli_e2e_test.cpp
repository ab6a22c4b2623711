// End-to-end: `inertial simulate` of the long serial chains (examples/chain14.urdf, chain28.urdf) at
// 1 kHz with viscous and Coulomb friction, which the fixed-step simulator with gains from the mass
// matrix's diagonal could not follow (issue 18, part 4), holds; and the torques it writes are
// Orocos KDL's inverse dynamics of the URDF (an implementation we did not write,
// formats/kdl_tree.hpp) plus the friction the command line states, at every sample.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <iostream>
#include <string>

#include "cli_support.hpp"
#include "formats/kdl_tree.hpp"
#include "inertial/formats/joint_csv.hpp"
#include "inertial/formats/urdf_model.hpp"
#include "simulated_robot.hpp"

namespace inertial {
namespace {

using testing::Contains;
using testing::Describe;
using testing::RunCli;
namespace fs = std::filesystem;

// The largest |tau - (KDL RNEA + 0.1 qd + 0.1 tanh(qd / 0.01))| over the log (default effect values
// 0.1, Coulomb's default velocity scale 0.01 rad/s), relative to the largest |tau|.
double WorstTorqueErrorAgainstKdl(const std::string& urdf, const JointSamples& s, double* largest_torque) {
  const std::string xml = testing::ReadFile(urdf);
  const RobotModel model = ParseUrdf(xml, urdf);
  const testing::KdlInverseDynamics kdl(xml, model);
  double worst = 0;
  *largest_torque = s.tau.cwiseAbs().maxCoeff();
  for (int i = 0; i < s.size(); ++i) {
    const Eigen::VectorXd q = s.q.row(i).transpose(), qd = s.qd.row(i).transpose(), qdd = s.qdd.row(i).transpose();
    const Eigen::VectorXd expected = kdl(q, qd, qdd, Vector3(0, 0, -9.81)) + 0.1 * qd +
                                     0.1 * (qd / 0.01).array().tanh().matrix();
    worst = std::max(worst, (s.tau.row(i).transpose() - expected).cwiseAbs().maxCoeff());
  }
  return worst / *largest_torque;
}

void ExpectSimulatesOnItsExcitation(int joints, const std::string& duration) {
  const std::string urdf = testing::Example("chain" + std::to_string(joints) + ".urdf");
  const fs::path csv = testing::UniqueTempPath("chain.csv");
  const auto start = std::chrono::steady_clock::now();
  const testing::CliRun r = RunCli({"simulate", "--model", urdf, "--duration", duration, "--rate", "1000", "--effects",
                                    "viscous,coulomb", "--out", csv.string()});
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  ASSERT_EQ(r.exit_code, 0) << Describe(r);
  EXPECT_FALSE(Contains(r.err, "diverged")) << Describe(r);
  const RobotModel robot = LoadUrdf(urdf);
  const JointSamples s = ReadJointCsv(csv.string(), robot.dof_names);
  ASSERT_EQ(s.size(), static_cast<int>(std::lround(std::stod(duration) * 1000)) + 1);
  // On the excitation (the command refuses a log more than 10 % of --amplitude off it): speeds of
  // the 0.9 rad, 0.1 Hz base excitation, not of a runaway.
  EXPECT_LT(s.qd.cwiseAbs().maxCoeff(), 10.0);
  double largest = 0;
  const double worst = WorstTorqueErrorAgainstKdl(urdf, s, &largest);
  std::cout << "chain" << joints << ", " << duration << " s at 1 kHz: " << seconds
            << " s wall; max |tau - KDL inverse dynamics - friction| / max |tau| = " << worst << " (max |tau| "
            << largest << " N m)\n";
  EXPECT_LT(worst, 1e-9);
  fs::remove(csv);
}

// The command of the issue: it failed at t = 0.005 s ("the mass matrix ... is not positive
// definite").
TEST(SimulateCliKdl, Chain14AtOneKilohertz) { ExpectSimulatesOnItsExcitation(14, "0.5"); }

// The 28-joint chain, 0.2 s of the 2 s the issue asks for (the whole run is measured in the README).
TEST(SimulateCliKdl, Chain28AtOneKilohertz) { ExpectSimulatesOnItsExcitation(28, "0.2"); }

}  // namespace
}  // namespace inertial
