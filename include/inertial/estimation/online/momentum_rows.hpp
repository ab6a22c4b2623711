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
/// whatever lambda, and whatever lambda does from one step to the next (both sides see the same
/// a_k). The filter trades noise for nothing else: the backward difference of P carries the
/// velocity noise differentiated, and F passes it up to its corner, so that part of the rows'
/// error grows as lambda (its std is about M lambda sigma_qd).
///
/// The corner follows the motion (kAdaptive, the default): f_c = kCornerPerMotion f_motion, with
/// f_motion the RMS frequency of the motion so far, sqrt(sum_j mean(qd_j^2) / sum_j var(q_j)) /
/// (2 pi) (the frequency of a sine with those velocity and position spreads), between kMinCutoffHz
/// and the given cutoff, once a period of f_motion has been seen (before: the floor). Why there: the velocity noise sigma_qd enters the rows differentiated, so
/// its part of a row's error grows as the corner (std about M lambda sigma_qd), and it sits in the
/// regressor, where least squares turns it into bias (errors in variables), while the motion's own
/// content stops growing once the corner is above the motion; below the motion both shrink alike
/// and the torque noise's share grows. The corner belongs at the top of the motion's band: a
/// multi-sine's RMS frequency lies inside its band, and 3 f_motion passes its content at >= 95 %
/// of its power up to f_motion. Measured (0.005 rad/s of velocity noise, 0.02 N m of torque noise,
/// held-out error / batch fit on exact qdd): the leg 1.26x at a fixed 20 Hz, 1.01x at 3 f_motion;
/// arm7 2.98x at 20 Hz, 1.02x at 3 f_motion; the KUKA LWR4+ (f_motion 0.08 Hz) alike at any corner.
/// Since the rows are exact at any lambda, a corner below the motion costs variance, never bias.
///
/// A step longer than half the given cutoff's period, 1 / (2 f_c), cannot carry the motion the
/// filter may pass (Nyquist), and the midpoint means over it would be guesses: the filters restart
/// there (the sample primes again). Restarting from zero states is exact too; it costs the rows'
/// weight for about 1 / lambda seconds. The motion's statistics are kept.
///
/// Allocation-free and exception-free per sample after construction. Holds no reference to the
/// model (its owner may move): Update takes it.
#pragma once

#include <Eigen/Core>

#include "inertial/model/momentum_features.hpp"

namespace inertial {

/// [Hz] the adaptive corner's floor: a time constant of 1.6 s.
inline constexpr double kMinCutoffHz = 0.1;
/// The adaptive corner over the motion's RMS frequency (the file comment).
inline constexpr double kCornerPerMotion = 3.0;

class MomentumRows {
 public:
  enum class Corner { kAdaptive, kFixed };
  /// @param cutoff_hz the filter's corner f_c (lambda = 2 pi f_c), > 0: kFixed, the corner;
  ///   kAdaptive, its ceiling (the file comment).
  /// @throws std::invalid_argument for a cutoff that is not positive and finite.
  MomentumRows(const RobotDynamics& model, double cutoff_hz, Corner corner = Corner::kAdaptive);

  /// Feeds sample (t, q, qd, tau) of `model` (the one constructed with, or a copy). The first
  /// sample (and the first after Reset or after a step over 1 / (2 f_c)) only primes the filter
  /// and returns false; later ones set A (num_dofs x num_features) and y (num_dofs) to the
  /// filtered row F[dP/dt] + F[H] and the filtered torque F[tau], and return true.
  /// Preconditions (debug-asserted): sizes; t after the previous sample's t.
  bool Update(const RobotDynamics& model, double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
              const Eigen::VectorXd& tau, Eigen::Ref<Eigen::MatrixXd> A, Eigen::Ref<Eigen::VectorXd> y);
  /// Forgets the filters' states: the next sample primes again (after a gap in the stream).
  void Reset();

  double cutoff_hz() const { return cutoff_hz_; }
  /// The corner the last row was filtered with [Hz].
  double corner_hz() const { return corner_hz_; }
  bool primed() const { return primed_; }
  /// The last row's unfiltered midpoint terms (valid after Update returned true): u = dP/dt + H
  /// at the step's midpoint and the midpoint torque, and the step [s]. u_tau - u w is the
  /// residual of the dynamics over the step, without lag and without the filter.
  const Eigen::MatrixXd& midpoint_row() const { return midpoint_row_; }
  const Eigen::VectorXd& midpoint_torque() const { return midpoint_tau_; }
  double last_step() const { return last_step_; }
  /// The time of the last sample fed (valid when primed).
  double last_time() const { return last_t_; }

 private:
  MomentumFeatures features_;
  double cutoff_hz_, corner_hz_;
  Corner corner_;
  // The motion's statistics (kAdaptive): sample count, per joint the sums of q - q_0 and its
  // square (shifted by the first sample, so no cancellation at a pose far from 0) and of qd^2.
  double motion_count_ = 0.0, t_first_ = 0.0;
  Eigen::VectorXd q_first_, q_sum_, q_square_sum_, qd_square_sum_;
  bool primed_ = false;
  double last_t_ = 0.0;
  Eigen::MatrixXd P_, H_, P_last_, H_last_, filtered_dP_;  ///< filtered_dP_: F[dP/dt + H]
  Eigen::VectorXd tau_last_, filtered_tau_;
  Eigen::MatrixXd midpoint_row_;
  Eigen::VectorXd midpoint_tau_;
  double last_step_ = 0.0;
};

}  // namespace inertial
