#include "inertial/model/body_torques.hpp"

#include <stdexcept>
#include <string>

namespace inertial {

Eigen::MatrixXd BodyTorques(const RobotDynamics& model, int e, const JointSamples& data) {
  if (e < 0 || e >= static_cast<int>(model.bodies().size())) {
    throw std::invalid_argument("body torques: the model has no estimated body " + std::to_string(e));
  }
  const int n = model.num_dofs();
  if (data.q.cols() != n || data.qd.cols() != n || data.qdd.cols() != n || data.q.rows() != data.size() ||
      data.qd.rows() != data.size() || data.qdd.rows() != data.size()) {
    throw std::invalid_argument("body torques: the samples must have " + std::to_string(n) + " joints");
  }
  const EstimatedBody& body = model.bodies()[static_cast<size_t>(e)];
  const Vector10 pi = body.prior.vector();
  Eigen::MatrixXd A(n, model.num_features());
  Eigen::MatrixXd tau(data.size(), n);
  for (int i = 0; i < data.size(); ++i) {
    model.Features(data.q.row(i).transpose(), data.qd.row(i).transpose(), data.qdd.row(i).transpose(), A);
    tau.row(i) = (A.middleCols<10>(10 * body.block) * pi).transpose();
  }
  return tau;
}

}  // namespace inertial
