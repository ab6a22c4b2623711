#include "inertial/estimation/online/momentum_rows.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include "inertial/inertia/assert.hpp"

namespace inertial {

MomentumRows::MomentumRows(const RobotDynamics& model, double cutoff_hz)
    : features_(model),
      cutoff_hz_(cutoff_hz),
      P_(model.num_dofs(), model.num_features()),
      H_(model.num_dofs(), model.num_features()),
      P_last_(model.num_dofs(), model.num_features()),
      H_last_(model.num_dofs(), model.num_features()),
      filtered_dP_(model.num_dofs(), model.num_features()),
      filtered_H_(model.num_dofs(), model.num_features()),
      tau_last_(model.num_dofs()),
      filtered_tau_(model.num_dofs()) {
  if (!(cutoff_hz > 0.0) || !std::isfinite(cutoff_hz)) {
    throw std::invalid_argument("momentum rows: the filter's cutoff must be a positive frequency, got " +
                                std::to_string(cutoff_hz) + " Hz");
  }
  Reset();
}

void MomentumRows::Reset() {
  primed_ = false;
  filtered_dP_.setZero();
  filtered_H_.setZero();
  filtered_tau_.setZero();
}

bool MomentumRows::Update(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd, const Eigen::VectorXd& tau,
                          Eigen::Ref<Eigen::MatrixXd> A, Eigen::Ref<Eigen::VectorXd> y) {
  INERTIAL_ASSERT(tau.size() == tau_last_.size() && A.rows() == P_.rows() && A.cols() == P_.cols() &&
                  y.size() == tau_last_.size());
  features_.Compute(q, qd, P_, H_);
  if (!primed_) {
    primed_ = true;
    last_t_ = t;
    P_last_ = P_;
    H_last_ = H_;
    tau_last_ = tau;
    return false;
  }
  const double dt = t - last_t_;
  INERTIAL_ASSERT(dt > 0.0);
  const double a = std::exp(-2.0 * M_PI * cutoff_hz_ * dt);
  const double b = 1.0 - a;
  filtered_dP_ = a * filtered_dP_ + (b / dt) * (P_ - P_last_);
  filtered_H_ = a * filtered_H_ + (0.5 * b) * (H_ + H_last_);
  filtered_tau_ = a * filtered_tau_ + (0.5 * b) * (tau + tau_last_);
  A = filtered_dP_ + filtered_H_;
  y = filtered_tau_;
  P_last_.swap(P_);
  H_last_.swap(H_);
  tau_last_ = tau;
  last_t_ = t;
  return true;
}

}  // namespace inertial
