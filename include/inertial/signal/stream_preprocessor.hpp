/// @file stream_preprocessor.hpp
/// The preprocessing stage of a sample stream (source -> decode -> preprocess -> estimator):
/// what the source did not measure is derived here and nowhere else, causally, so the daemon and a
/// replay of its log compute the same numbers. A sample without qdd (has_qdd false: a message
/// without accelerations, a CAN tick) gets qdd from qd by causal_acceleration.hpp; a sample with
/// qdd passes unchanged. A derived qdd is for consumers that want an acceleration (the stream
/// diagnosis): the sample's qdd_measured stays false, and the online estimator fits rows that need
/// no qdd (momentum_rows.hpp) instead. Time order is enforced first, because the filter differences in time.
/// Allocation-free after the first sample; never throws.
///
/// Offline logs are differentiated as a whole instead (Savitzky-Golay, log_differentiation.hpp).
#pragma once

#include <string>

#include "inertial/signal/causal_acceleration.hpp"
#include "inertial/model/joint_samples.hpp"
#include "inertial/signal/rejection.hpp"

namespace inertial {

class StreamPreprocessor {
 public:
  /// @param num_joints of every sample; @param accel_cutoff_hz > 0, the low-pass of the derived qdd.
  StreamPreprocessor(int num_joints, double accel_cutoff_hz);

  /// Completes *sample in place. Rejection::kNone: pass it on. Else it is not passed on, and
  /// *why (optional) says why: kOutOfOrder (t not after the previous sample's), kPriming (the
  /// first sample without qdd only primes the filter), kNonFinite (the derived qdd overflowed:
  /// qd jumped too far in too short a time; the filter starts again at the next sample),
  /// kWrongSize (not num_joints values).
  Rejection Process(JointSample* sample, std::string* why = nullptr);

  double accel_cutoff_hz() const { return cutoff_hz_; }

 private:
  int num_joints_;
  double cutoff_hz_;
  bool started_ = false;
  double last_t_ = 0.0;
  CausalAcceleration acceleration_;
};

}  // namespace inertial
