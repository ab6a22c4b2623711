// Fuzz harness: a URDF (or model file with <inertial_effects>) through our validation and urdfdom
// (urdf_model.hpp), then the identification model of what was accepted and one prediction.
#include "fuzz_support.hpp"
#include "inertial/estimation/batch/joint_identification.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace inertial;
  RobotModel robot;
  try {
    robot = ParseUrdf(fuzz::Text(data, size), "fuzz.urdf");
  } catch (const UrdfError&) {
    return 0;
  }
  if (robot.dof_names.size() != static_cast<std::size_t>(robot.tree.num_dofs())) fuzz::Fail("DOF names and tree disagree");
  RobotDynamics model = MakeRobotDynamics(robot, {});
  try {
    model = MakeRobotDynamics(robot, robot.DeclaredEffects());
  } catch (const std::invalid_argument&) {
    // An effect the file states that the model cannot carry: refused by name, as the tools do.
  }
  const int n = model.num_dofs();
  JointSamples one;
  one.joint_names = robot.dof_names;
  one.t = Eigen::VectorXd::Zero(1);
  one.q = one.qd = one.qdd = Eigen::MatrixXd::Constant(1, n, 0.1);
  one.tau = Eigen::MatrixXd::Zero(1, n);
  const Eigen::MatrixXd tau = PredictJointTorques(model, Eigen::VectorXd::Zero(model.num_parameters()), one);
  if (tau.rows() != 1 || tau.cols() != n) fuzz::Fail("a prediction of the wrong size");
  for (const EstimatedBody& body : model.bodies()) (void)CheckConsistency(body.prior);
  return 0;
}
