#include "inertial/formats/torque_predictions.hpp"

#include "inertial/formats/joint_csv.hpp"

namespace inertial {

std::vector<std::string> TorquePredictionHeader(const RobotDynamics& model) {
  std::vector<std::string> header{"t"};
  for (const std::string& j : model.dof_names()) header.push_back("tau_hat_" + j);
  return header;
}

void WriteTorquePredictions(const std::string& path, const RobotDynamics& model, const Eigen::VectorXd& x,
                            const JointSamples& data) {
  const Eigen::MatrixXd tau = PredictJointTorques(model, x, data);
  Eigen::MatrixXd columns(data.size(), 1 + model.num_dofs());
  columns << data.t, tau;
  WriteColumnsCsv(path, TorquePredictionHeader(model), columns);
}

}  // namespace inertial
