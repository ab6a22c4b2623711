/// @file causal_acceleration.hpp
/// Joint accelerations online, from velocities alone: the backward difference of qd, low-passed
/// by a first-order filter at cutoff_hz (alpha = dt / (dt + 1 / (2 pi f_c)) per step). Causal, so
/// it lags; for logs, Savitzky-Golay (savitzky_golay.hpp) is better. Allocation-free after the
/// first sample; the first sample only primes it.
#pragma once

#include <Eigen/Core>

namespace inertial {

/// The gain of the first-order low-pass the derived qdd is filtered with, per step dt at corner
/// cutoff_hz: alpha = dt / (dt + 1 / (2 pi f_c)) (y += alpha (x - y)). Shared by whatever must be
/// filtered as the derived qdd is (the online estimator's stream residual).
inline double CausalLowPassGain(double dt, double cutoff_hz) {
  constexpr double kTwoPi = 6.283185307179586;
  return dt / (dt + 1.0 / (kTwoPi * cutoff_hz));
}

class CausalAcceleration {
 public:
  /// @param num_joints the size of qd; @param cutoff_hz > 0.
  CausalAcceleration(int num_joints, double cutoff_hz);

  /// Feeds (t, qd); false for the first sample (nothing to difference yet), else *qdd is set.
  /// Precondition: t after the previous sample's t, qd of num_joints entries.
  bool Update(double t, const Eigen::VectorXd& qd, Eigen::VectorXd* qdd);
  bool primed() const { return primed_; }
  double last_time() const { return last_t_; }

 private:
  double cutoff_hz_;
  bool primed_ = false;
  double last_t_ = 0.0;
  Eigen::VectorXd last_qd_, filtered_;
};

}  // namespace inertial
