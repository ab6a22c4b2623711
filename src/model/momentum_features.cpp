#include "inertial/model/momentum_features.hpp"

#include "inertial/inertia/assert.hpp"

namespace inertial {

MomentumFeatures::MomentumFeatures(const RobotDynamics& model)
    : workspace_(model.MakeWorkspace()),
      zero_(Eigen::VectorXd::Zero(model.num_dofs())),
      q_shifted_(model.num_dofs()),
      scratch_(model.num_dofs(), model.num_features()),
      plus_(model.num_dofs(), model.num_features()),
      minus_(model.num_dofs(), model.num_features()) {}

void MomentumFeatures::MomentumAt(const RobotDynamics& model, const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                                  Eigen::Ref<Eigen::MatrixXd> out) {
  model.Features(q, zero_, v, &workspace_, out);
  model.Features(q, zero_, zero_, &workspace_, scratch_);
  out -= scratch_;
}

void MomentumFeatures::Compute(const RobotDynamics& model, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                               Eigen::Ref<Eigen::MatrixXd> P, Eigen::Ref<Eigen::MatrixXd> H) {
  [[maybe_unused]] const int n = model.num_dofs();
  [[maybe_unused]] const int f = model.num_features();
  INERTIAL_ASSERT(q.size() == n && qd.size() == n && P.rows() == n && P.cols() == f && H.rows() == n && H.cols() == f &&
                  scratch_.rows() == n && scratch_.cols() == f);
  MomentumAt(model, q, qd, P);
  model.Features(q, qd, zero_, &workspace_, H);
  const double fastest = qd.cwiseAbs().maxCoeff();
  if (!(fastest > 0.0)) return;  // at rest Mdot qd = 0
  const double h = kDirectionalStep / fastest;
  q_shifted_ = q + h * qd;
  MomentumAt(model, q_shifted_, qd, plus_);
  q_shifted_ = q - h * qd;
  MomentumAt(model, q_shifted_, qd, minus_);
  H.noalias() -= (0.5 / h) * (plus_ - minus_);
}

}  // namespace inertial
