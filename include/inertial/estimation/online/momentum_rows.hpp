/// @file momentum_rows.hpp
/// Rows of the joint-torque regression that need no joint acceleration (issue 46): the momentum
/// form tau = d/dt [P w] + H w (model/momentum_features.hpp) filtered on both sides by one causal
/// first-order filter F(s) = lambda / (s + lambda) (Slotine and Li, "Composite adaptive control of
/// robot manipulators", Automatica 1989):
///   F[tau] = (F[dP/dt] + F[H]) w.
/// Discrete, between samples k-1 and k (step dt_k, any spacing):
///   u_dP = (P_k - P_{k-1}) / dt_k,   u_H = (H_k + H_{k-1}) / 2,   u_tau = (tau_k + tau_{k-1}) / 2,
/// each the value at the interval's midpoint to O(dt^2) (the backward difference of p is its
/// derivative there), and each filtered alike, y <- a y + (1 - a) u with a = exp(-lambda dt_k).
/// All states start at zero (as if the robot had been at rest with zero torque before the first
/// sample), which keeps the equation exact from the first row on: no lag between the two sides,
/// whatever lambda. The filter trades noise for nothing else: the backward difference of P carries
/// the velocity noise divided by dt, and F passes about lambda dt of it.
///
/// Allocation-free and exception-free per sample after construction.
#pragma once

#include <Eigen/Core>

#include "inertial/model/momentum_features.hpp"

namespace inertial {

class MomentumRows {
 public:
  /// @param cutoff_hz the filter's corner f_c (lambda = 2 pi f_c), > 0.
  /// @throws std::invalid_argument for a cutoff that is not positive and finite.
  MomentumRows(const RobotDynamics& model, double cutoff_hz);

  /// Feeds sample (t, q, qd, tau). The first sample (and the first after Reset) only primes the
  /// filter and returns false; later ones set A (num_dofs x num_features) and y (num_dofs) to the
  /// filtered row F[dP/dt] + F[H] and the filtered torque F[tau], and return true.
  /// Preconditions (debug-asserted): sizes; t after the previous sample's t.
  bool Update(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd, const Eigen::VectorXd& tau,
              Eigen::Ref<Eigen::MatrixXd> A, Eigen::Ref<Eigen::VectorXd> y);
  /// Forgets the filters' states: the next sample primes again (after a gap in the stream).
  void Reset();

  double cutoff_hz() const { return cutoff_hz_; }
  bool primed() const { return primed_; }

 private:
  MomentumFeatures features_;
  double cutoff_hz_;
  bool primed_ = false;
  double last_t_ = 0.0;
  Eigen::MatrixXd P_, H_, P_last_, H_last_, filtered_dP_, filtered_H_;
  Eigen::VectorXd tau_last_, filtered_tau_;
};

}  // namespace inertial
