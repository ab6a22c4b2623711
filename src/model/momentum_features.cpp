#include "inertial/model/momentum_features.hpp"

#include "inertial/inertia/assert.hpp"

namespace inertial {

MomentumFeatures::MomentumFeatures(const RobotDynamics& model)
    : model_(&model),
      workspace_(model.MakeWorkspace()),
      zero_(Eigen::VectorXd::Zero(model.num_dofs())),
      q_shifted_(model.num_dofs()),
      scratch_(model.num_dofs(), model.num_features()),
      plus_(model.num_dofs(), model.num_features()),
      minus_(model.num_dofs(), model.num_features()) {}

void MomentumFeatures::MomentumAt(const Eigen::VectorXd& q, const Eigen::VectorXd& v, Eigen::Ref<Eigen::MatrixXd> out) {
  model_->Features(q, zero_, v, &workspace_, out);
  model_->Features(q, zero_, zero_, &workspace_, scratch_);
  out -= scratch_;
}

void MomentumFeatures::Compute(const Eigen::VectorXd& q, const Eigen::VectorXd& qd, Eigen::Ref<Eigen::MatrixXd> P,
                               Eigen::Ref<Eigen::MatrixXd> H) {
  const int n = model_->num_dofs();
  const int f = model_->num_features();
  INERTIAL_ASSERT(q.size() == n && qd.size() == n && P.rows() == n && P.cols() == f && H.rows() == n && H.cols() == f);
  MomentumAt(q, qd, P);
  model_->Features(q, qd, zero_, &workspace_, H);
  const double fastest = qd.cwiseAbs().maxCoeff();
  if (!(fastest > 0.0)) return;  // at rest Mdot qd = 0
  const double h = kDirectionalStep / fastest;
  q_shifted_ = q + h * qd;
  MomentumAt(q_shifted_, qd, plus_);
  q_shifted_ = q - h * qd;
  MomentumAt(q_shifted_, qd, minus_);
  H.noalias() -= (0.5 / h) * (plus_ - minus_);
}

}  // namespace inertial
