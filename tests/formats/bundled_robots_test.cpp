// examples/bundled_robots.hpp (the bundled robots written out in code, for programs that use the
// core alone) against the URDF files as the I/O layer loads them: the same joints, the same link
// inertias to the URDF's printed digits, and the same inverse dynamics with rotors, friction and a
// payload on the named links.
#include "examples/bundled_robots.hpp"

#include <gtest/gtest.h>

#include "inertial/formats/model_file.hpp"
#include "simulated_robot.hpp"

namespace inertial {
namespace {

void ExpectSameRobot(const examples::BundledRobot& coded, const std::string& urdf, const std::string& effects) {
  const RobotModel loaded = LoadUrdf(testing::Example(urdf));
  ASSERT_EQ(coded.links.num_bodies(), loaded.tree.num_bodies());
  EXPECT_EQ(coded.dof_names, loaded.dof_names);
  for (int i = 0; i < loaded.tree.num_bodies(); ++i) {
    const JointModel &a = coded.links.joint(i), &b = loaded.tree.joint(i);
    EXPECT_EQ(coded.links.body_name(i), loaded.tree.body_name(i));
    EXPECT_EQ(coded.links.parent(i), loaded.tree.parent(i));
    EXPECT_LT((a.p_parent_joint - b.p_parent_joint).norm(), 1e-15) << a.name;
    EXPECT_LT((a.R_parent_joint - b.R_parent_joint).norm(), 1e-15) << a.name;
    EXPECT_LT((a.axis - b.axis).norm(), 1e-15) << a.name;
    // The URDF prints inertias to 6 significant digits: 1e-6 of the link's largest entry.
    const Vector10 pa = coded.links.inertia(i).vector(), pb = loaded.tree.inertia(i).vector();
    EXPECT_LT((pa - pb).cwiseAbs().maxCoeff(), 1e-6 * pb.cwiseAbs().maxCoeff()) << coded.links.body_name(i) << "\n"
                                                                               << pa.transpose() << "\n"
                                                                               << pb.transpose();
  }
  const RobotDynamics from_code = coded.Dynamics(effects);
  const RobotDynamics from_file = MakeRobotDynamics(loaded, ParseEffectList(effects));
  ASSERT_EQ(from_code.num_parameters(), from_file.num_parameters());
  testing::Rng rng(41);
  const int n = from_file.num_dofs();
  for (int trial = 0; trial < 10; ++trial) {
    const Eigen::VectorXd x = Eigen::VectorXd::NullaryExpr(from_file.num_parameters(), [&] { return rng.Uniform(-0.3, 0.3); });
    const Eigen::VectorXd q = Eigen::VectorXd::NullaryExpr(n, [&] { return rng.Uniform(-2, 2); });
    const Eigen::VectorXd qd = Eigen::VectorXd::NullaryExpr(n, [&] { return rng.Uniform(-2, 2); });
    const Eigen::VectorXd qdd = Eigen::VectorXd::NullaryExpr(n, [&] { return rng.Uniform(-2, 2); });
    const Eigen::VectorXd expected = from_file.InverseDynamics(x, q, qd, qdd);
    EXPECT_LT((from_code.InverseDynamics(x, q, qd, qdd) - expected).norm(), 1e-5 * (1 + expected.norm())) << trial;
  }
}

TEST(BundledRobots, Leg3InCodeIsTheUrdf) {
  ExpectSameRobot(examples::Leg3(), "leg3.urdf",
                  "viscous,coulomb,rotor@abad:gear=6,rotor@hip:gear=6,rotor@knee:gear=9.33,payload@foot:mass=0.2");
}

TEST(BundledRobots, Arm7InCodeIsTheUrdf) {
  ExpectSameRobot(examples::Arm7(), "arm7.urdf", "viscous,coulomb,payload@tool0:mass=0.5");
}

TEST(BundledRobots, ChainsInCodeAreTheUrdfs) {
  for (const int n : {7, 14, 28}) {
    SCOPED_TRACE(n);
    ExpectSameRobot(examples::Chain(n), "chain" + std::to_string(n) + ".urdf", "viscous,coulomb");
  }
}

}  // namespace
}  // namespace inertial
