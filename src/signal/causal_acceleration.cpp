#include "inertial/signal/causal_acceleration.hpp"

#include <cmath>

namespace inertial {

CausalAcceleration::CausalAcceleration(int n, double cutoff_hz)
    : cutoff_hz_(cutoff_hz), last_qd_(Eigen::VectorXd::Zero(n)), filtered_(Eigen::VectorXd::Zero(n)) {}

bool CausalAcceleration::Update(double t, const Eigen::VectorXd& qd, Eigen::VectorXd* qdd) {
  if (!primed_) {
    primed_ = true;
    last_t_ = t;
    last_qd_ = qd;
    filtered_.setZero();
    return false;
  }
  const double dt = t - last_t_;
  const double alpha = CausalLowPassGain(dt, cutoff_hz_);
  filtered_ += alpha * ((qd - last_qd_) / dt - filtered_);
  *qdd = filtered_;
  last_qd_ = qd;
  last_t_ = t;
  return true;
}

}  // namespace inertial
