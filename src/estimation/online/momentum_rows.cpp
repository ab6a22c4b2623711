#include "inertial/estimation/online/momentum_rows.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "inertial/inertia/assert.hpp"

namespace inertial {

MomentumRows::MomentumRows(const RobotDynamics& model, double cutoff_hz, Corner corner)
    : features_(model),
      cutoff_hz_(cutoff_hz),
      corner_hz_(cutoff_hz),
      corner_(corner),
      q_first_(Eigen::VectorXd::Zero(model.num_dofs())),
      q_sum_(Eigen::VectorXd::Zero(model.num_dofs())),
      q_square_sum_(Eigen::VectorXd::Zero(model.num_dofs())),
      qd_square_sum_(Eigen::VectorXd::Zero(model.num_dofs())),
      P_(model.num_dofs(), model.num_features()),
      H_(model.num_dofs(), model.num_features()),
      P_last_(model.num_dofs(), model.num_features()),
      H_last_(model.num_dofs(), model.num_features()),
      filtered_dP_(model.num_dofs(), model.num_features()),
      tau_last_(model.num_dofs()),
      filtered_tau_(model.num_dofs()),
      midpoint_row_(Eigen::MatrixXd::Zero(model.num_dofs(), model.num_features())),
      midpoint_tau_(Eigen::VectorXd::Zero(model.num_dofs())) {
  if (!(cutoff_hz > 0.0) || !std::isfinite(cutoff_hz)) {
    throw std::invalid_argument("momentum rows: the filter's cutoff must be a positive frequency, got " +
                                std::to_string(cutoff_hz) + " Hz");
  }
  Reset();
}

void MomentumRows::Reset() {
  primed_ = false;
  filtered_dP_.setZero();
  filtered_tau_.setZero();
}

bool MomentumRows::Update(const RobotDynamics& model, double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                          const Eigen::VectorXd& tau, Eigen::Ref<Eigen::MatrixXd> A, Eigen::Ref<Eigen::VectorXd> y) {
  INERTIAL_ASSERT(tau.size() == tau_last_.size() && A.rows() == P_.rows() && A.cols() == P_.cols() &&
                  y.size() == tau_last_.size());
  features_.Compute(model, q, qd, P_, H_);
  if (corner_ == Corner::kAdaptive) {
    if (motion_count_ == 0.0) {
      q_first_ = q;
      t_first_ = t;
    }
    motion_count_ += 1.0;
    q_sum_ += q - q_first_;
    q_square_sum_ += (q - q_first_).cwiseAbs2();
    qd_square_sum_ += qd.cwiseAbs2();
    const double position_variance = (q_square_sum_ - q_sum_.cwiseAbs2() / motion_count_).sum() / motion_count_;
    const double velocity_square = qd_square_sum_.sum() / motion_count_;
    const double f_motion = std::sqrt(velocity_square / position_variance) / (2.0 * M_PI);
    // A frequency is known once a period of it has been seen: before (a motion just started from
    // rest looks faster than it is: q - q_0 grows as t^2, qd as t, the estimate as 0.6 / t, whose
    // period 1.6 t is longer than what was seen), and at rest (0/0), the floor.
    const bool known = std::isfinite(f_motion) && (t - t_first_) * f_motion >= 1.0;
    corner_hz_ = known ? std::clamp(kCornerPerMotion * f_motion, kMinCutoffHz, cutoff_hz_) : std::min(kMinCutoffHz, cutoff_hz_);
  }
  if (primed_ && t - last_t_ > 0.5 / cutoff_hz_) Reset();  // a gap longer than the filter's Nyquist step
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
  const double a = std::exp(-2.0 * M_PI * corner_hz_ * dt);
  const double b = 1.0 - a;
  midpoint_row_ = (P_ - P_last_) / dt + 0.5 * (H_ + H_last_);
  midpoint_tau_ = 0.5 * (tau + tau_last_);
  last_step_ = dt;
  filtered_dP_ = a * filtered_dP_ + b * midpoint_row_;  // dP/dt and H in one state: F is linear
  filtered_tau_ = a * filtered_tau_ + b * midpoint_tau_;
  A = filtered_dP_;
  y = filtered_tau_;
  P_last_.swap(P_);
  H_last_.swap(H_);
  tau_last_ = tau;
  last_t_ = t;
  return true;
}

}  // namespace inertial
