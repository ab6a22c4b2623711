// End-to-end tests of `inertial simulate`: the log it writes obeys the CSV contract, its torques are
// the true robot's (rebuilt independently from the --truth JSON and run through recursive
// Newton-Euler) plus the stated effects, and bad options are refused.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>

#include "cli_support.hpp"
#include "inertial/formats/joint_csv.hpp"
#include "inertial/formats/urdf_model.hpp"
#include "inertial/model/joint_limits.hpp"
#include "simulated_robot.hpp"

namespace inertial {
namespace {

using testing::Contains;
using testing::Describe;
using testing::RunCli;
namespace fs = std::filesystem;

// Every sample of s inside the model's <limit>s (positions, speeds, torques).
void ExpectWithinLimits(const JointSamples& s, const RobotModel& robot) {
  for (int j = 0; j < static_cast<int>(robot.dof_limits.size()); ++j) {
    const JointLimits& l = robot.dof_limits[j];
    EXPECT_GE(s.q.col(j).minCoeff(), l.lower) << robot.dof_names[j];
    EXPECT_LE(s.q.col(j).maxCoeff(), l.upper) << robot.dof_names[j];
    EXPECT_LE(s.qd.col(j).cwiseAbs().maxCoeff(), l.velocity) << robot.dof_names[j];
    EXPECT_LE(s.tau.col(j).cwiseAbs().maxCoeff(), l.effort) << robot.dof_names[j];
  }
}

TEST(SimulateCli, KeepsToTheUrdfsJointLimits) {
  // The leg's knee may move in [0.3, 2.7] rad: the default excitation (0.9 rad about 0) would leave
  // it, so it is centred at 1.5 rad; --ignore-limits excites about 0 and leaves the range.
  const RobotModel leg = LoadUrdf(testing::Example("leg3.urdf"));
  const int knee = leg.DofIndex("knee");
  ASSERT_EQ(leg.dof_limits[knee].lower, 0.3);
  const fs::path csv = testing::UniqueTempPath("limits.csv");
  testing::CliRun r = RunCli({"simulate", "--model", testing::Example("leg3.urdf"), "--duration", "10", "--out", csv.string()});
  ASSERT_EQ(r.exit_code, 0) << Describe(r);
  JointSamples s = ReadJointCsv(csv.string(), leg.dof_names);
  ExpectWithinLimits(s, leg);
  EXPECT_GT(s.q.col(knee).maxCoeff() - s.q.col(knee).minCoeff(), 0.5);  // still excited
  r = RunCli({"simulate", "--model", testing::Example("leg3.urdf"), "--duration", "10", "--ignore-limits", "--out", csv.string()});
  ASSERT_EQ(r.exit_code, 0) << Describe(r);
  EXPECT_LT(ReadJointCsv(csv.string(), leg.dof_names).q.col(knee).minCoeff(), 0.3);

  // The arm's joints turn at 1.31 .. 2.36 rad/s at most: at a 0.4 Hz base frequency the excitation
  // is scaled down joint by joint, and each scaled joint is named.
  const RobotModel arm = LoadUrdf(testing::Example("arm7.urdf"));
  r = RunCli({"simulate", "--model", testing::Example("arm7.urdf"), "--duration", "5", "--base-frequency", "0.4", "--out",
              csv.string()});
  ASSERT_EQ(r.exit_code, 0) << Describe(r);
  EXPECT_TRUE(Contains(r.err, "note: joint 'joint4': excitation scaled by")) << Describe(r);
  EXPECT_TRUE(Contains(r.err, "to keep |qd| within its velocity limit 1.31")) << Describe(r);
  s = ReadJointCsv(csv.string(), arm.dof_names);
  ExpectWithinLimits(s, arm);
  // 95 % of the limit, reached within a few per cent (the top speed is taken on the log's grid).
  EXPECT_GT(s.qd.col(3).cwiseAbs().maxCoeff(), 0.9 * 1.31);
  fs::remove(csv);
}

TEST(SimulateCli, RefusesAnExcitationBeyondAnEffortLimit) {
  // The leg with every joint's effort limit at 0.5 N m: holding the leg against gravity needs more.
  std::string urdf = testing::ReadFile(testing::Example("leg3.urdf"));
  for (std::size_t at = urdf.find("effort=\""); at != std::string::npos; at = urdf.find("effort=\"", at + 1)) {
    urdf.replace(at + 8, urdf.find('"', at + 8) - (at + 8), "0.5");
  }
  const fs::path model = testing::UniqueTempPath("weak.urdf"), csv = testing::UniqueTempPath("weak.csv");
  std::ofstream(model) << urdf;
  const testing::CliRun r = RunCli({"simulate", "--model", model.string(), "--duration", "2", "--out", csv.string()});
  EXPECT_EQ(r.exit_code, 3) << Describe(r);
  EXPECT_TRUE(Contains(r.err, "Error: simulation refused: at t = ")) << Describe(r);
  EXPECT_TRUE(Contains(r.err, "beyond its URDF effort limit 0.5; lower --amplitude")) << Describe(r);
  EXPECT_FALSE(fs::exists(csv));  // nothing written
  fs::remove(model);
}

TEST(SimulateCli, TorquesAreTheTrueRobotsPlusItsEffects) {
  const fs::path csv = testing::UniqueTempPath("sim.csv"), truth = testing::UniqueTempPath("truth.json");
  const testing::CliRun r =
      RunCli({"simulate", "--model", testing::Example("leg3.urdf"), "--effects", "viscous,coulomb@knee:scale=0.05,offset@hip",
              "--effect-values", "0.2,0.3,0.4,0.9,-1.5", "--perturb", "0.2", "--duration", "4", "--rate", "250", "--out",
              csv.string(), "--truth", truth.string()});
  ASSERT_EQ(r.exit_code, 0) << Describe(r);
  const RobotModel robot = LoadUrdf(testing::Example("leg3.urdf"));
  const JointSamples s = ReadJointCsv(csv.string(), robot.dof_names);
  ASSERT_EQ(s.size(), 1001);
  EXPECT_NEAR(s.t[1000], 4.0, 1e-12);
  EXPECT_LT(s.qd.cwiseAbs().maxCoeff(), 10.0);  // on the excitation (amplitude 0.9 rad, 0.1 Hz base)
  const nlohmann::json j = nlohmann::json::parse(testing::ReadFile(truth));
  // The true links, rebuilt from the truth file on the URDF's joints.
  KinematicTree tree;
  for (int b = 0; b < robot.tree.num_bodies(); ++b) {
    const std::vector<double> pi = j["bodies"][b]["pi"];
    ASSERT_EQ(j["bodies"][b]["name"], robot.tree.body_name(b));
    tree.AddBody(robot.tree.body_name(b), robot.tree.parent(b), robot.tree.joint(b),
                 InertialParams::FromVector(Eigen::Map<const Vector10>(pi.data())));
  }
  // The links differ from the URDF (perturbed) ...
  EXPECT_GT((tree.StackedParameters() - robot.tree.StackedParameters()).norm(), 1e-3);
  // ... and the torques are theirs plus viscous (0.2, 0.3, 0.4 N m s/rad), Coulomb on the knee
  // (0.9 N m, tanh(qd / 0.05)) and the hip's offset (-1.5 N m).
  double worst = 0;
  for (int k = 0; k < s.size(); k += 13) {
    const Eigen::VectorXd qd = s.qd.row(k).transpose();
    Eigen::VectorXd tau = tree.InverseDynamics(s.q.row(k).transpose(), qd, s.qdd.row(k).transpose());
    tau += Eigen::Vector3d(0.2, 0.3, 0.4).cwiseProduct(qd);
    tau[2] += 0.9 * std::tanh(qd[2] / 0.05);
    tau[1] += -1.5;
    worst = std::max(worst, (tau - s.tau.row(k).transpose()).cwiseAbs().maxCoeff());
  }
  EXPECT_LT(worst, 1e-9);
}

TEST(SimulateCli, PositionsOnlyAndBadOptions) {
  const fs::path csv = testing::UniqueTempPath("pos.csv");
  const std::string leg = testing::Example("leg3.urdf");
  testing::CliRun r = RunCli({"simulate", "--model", leg, "--duration", "1", "--positions-only", "--out", csv.string()});
  ASSERT_EQ(r.exit_code, 0) << Describe(r);
  std::ifstream in(csv);
  std::string header;
  std::getline(in, header);
  EXPECT_EQ(header, "t,q_abad,q_hip,q_knee,tau_abad,tau_hip,tau_knee");
  r = RunCli({"simulate", "--model", leg, "--rate", "0", "--out", csv.string()});
  EXPECT_EQ(r.exit_code, 2) << Describe(r);
  r = RunCli({"simulate", "--model", leg, "--effects", "viscous", "--effect-values", "-1", "--out", csv.string()});
  EXPECT_EQ(r.exit_code, 3) << Describe(r);
  EXPECT_TRUE(Contains(r.err, "viscous@abad must be >= 0")) << r.err;
  r = RunCli({"simulate", "--model", leg, "--seed", "x", "--out", csv.string()});
  EXPECT_EQ(r.exit_code, 3) << Describe(r);
  r = RunCli({"simulate", "--model", leg, "--out", "/nonexistent/dir/x.csv"});
  EXPECT_EQ(r.exit_code, 5) << Describe(r);
}

// A long run shows its progress on stderr when stderr is a terminal (a pseudo-terminal from
// util-linux's `script` here), erased before the results; in a pipe or a file nothing is added.
TEST(SimulateCli, ShowsProgressOnATerminalOnly) {
  if (std::system("command -v script > /dev/null 2>&1") != 0) GTEST_SKIP() << "no `script` (util-linux) to make a terminal";
  const char* cli = std::getenv("INERTIAL_CLI");
  ASSERT_NE(cli, nullptr);
  const fs::path csv = testing::UniqueTempPath("progress.csv"), captured = testing::UniqueTempPath("tty.txt");
  const std::string command = std::string(cli) + " simulate --model " + testing::Example("leg3.urdf") + " --out " +
                              csv.string() + " --duration 30";
  ASSERT_EQ(std::system(("script -qec '" + command + "' " + captured.string() + " > /dev/null 2>&1").c_str()), 0);
  const std::string tty = testing::ReadFile(captured);
  EXPECT_TRUE(Contains(tty, "\rsimulate: ")) << tty;
  EXPECT_TRUE(Contains(tty, " %")) << tty;
  // The line is erased (carriage return, blanks, carriage return) before the result is printed.
  const std::size_t wrote = tty.find("wrote ");
  ASSERT_NE(wrote, std::string::npos) << tty;
  EXPECT_EQ(tty.rfind("\rsimulate: ", wrote) < wrote, true);
  EXPECT_EQ(tty[wrote - 1], '\r') << tty;
  const testing::CliRun piped = RunCli({"simulate", "--model", testing::Example("leg3.urdf"), "--out", csv.string(),
                                        "--duration", "30"});
  ASSERT_EQ(piped.exit_code, 0) << Describe(piped);
  EXPECT_FALSE(Contains(piped.err, "simulate: ")) << piped.err;
  fs::remove(csv);
  fs::remove(captured);
}

}  // namespace
}  // namespace inertial
