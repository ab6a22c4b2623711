#include "inertial/signal/stream_preprocessor.hpp"

#include <cmath>

namespace inertial {

StreamPreprocessor::StreamPreprocessor(int num_joints, double accel_cutoff_hz)
    : num_joints_(num_joints), cutoff_hz_(accel_cutoff_hz), acceleration_(num_joints, accel_cutoff_hz) {}

Rejection StreamPreprocessor::Process(JointSample* s, std::string* why) {
  if (s->qd.size() != num_joints_ || (s->has_qdd && s->qdd.size() != num_joints_)) {
    if (why) *why = "qd or qdd does not have " + std::to_string(num_joints_) + " values";
    return Rejection::kWrongSize;
  }
  if (started_ && !(s->t > last_t_)) {
    if (why) *why = "time " + std::to_string(s->t) + " s does not follow " + std::to_string(last_t_) + " s";
    return Rejection::kOutOfOrder;
  }
  started_ = true;
  last_t_ = s->t;
  if (s->has_qdd) return Rejection::kNone;
  if (!acceleration_.Update(s->t, s->qd, &s->qdd)) {
    if (why) *why = "the first sample primes the acceleration filter";
    return Rejection::kPriming;
  }
  if (!s->qdd.allFinite()) {
    // qd changed too much in too little time for its difference quotient (found by the message
    // fuzz harness): the sample is refused and the filter starts again at the next one.
    acceleration_ = CausalAcceleration(num_joints_, cutoff_hz_);
    if (why) *why = "the acceleration derived from qd is not finite";
    return Rejection::kNonFinite;
  }
  s->has_qdd = true;
  s->qdd_measured = false;  // derived: the estimator uses rows without qdd (momentum_rows.hpp)
  return Rejection::kNone;
}

}  // namespace inertial
