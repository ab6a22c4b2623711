#include "inertial/runtime/sample_decoder.hpp"

#include "inertial/transport/body_message.hpp"

namespace inertial {

SampleDecoder SampleDecoder::JointMessages(JointMessageFormat format, std::vector<std::string> dof_names) {
  SampleDecoder d(Mode::kJoint);
  d.joint_.emplace(std::move(format), std::move(dof_names));
  return d;
}

SampleDecoder SampleDecoder::BodyWrenches() { return SampleDecoder(Mode::kBody); }

SampleDecoder SampleDecoder::CanFrames(CanConfig config, std::vector<std::string> dof_names) {
  SampleDecoder d(Mode::kCan);
  d.can_.emplace(std::move(config), std::move(dof_names));
  return d;
}

bool SampleDecoder::DecodeMessage(const void* data, std::size_t size, std::int64_t recv_utime, Sample* sample,
                                  std::string* why) {
  ++counters_.received;
  last_ = mode_ == Mode::kBody ? DecodeBodyWrench(data, size, &sample->body, why)
                               : joint_->Decode(data, size, recv_utime, &sample->joint, why);
  if (last_ != Rejection::kNone) {
    counters_.Reject(last_);
    return false;
  }
  ++counters_.accepted;
  return true;
}

bool SampleDecoder::DecodeFrame(const CanFrame& frame, Sample* sample, std::string* why) {
  const bool tick = can_->Feed(frame, &sample->joint, why);
  last_ = can_->last_rejection();
  return tick;
}

void SampleDecoder::CountBadLine() {
  ++bad_lines_;
  last_ = Rejection::kBadLine;
}

SampleCounters SampleDecoder::counters() const {
  if (mode_ != Mode::kCan) return counters_;
  SampleCounters c = can_->counters();
  c.received += bad_lines_;
  c.Reject(Rejection::kBadLine, bad_lines_);
  return c;
}

double SampleDecoder::accel_cutoff_hz() const {
  switch (mode_) {
    case Mode::kJoint: return joint_->format().accel_cutoff_hz;
    case Mode::kCan: return can_->config().accel_cutoff_hz;
    case Mode::kBody: break;
  }
  return 0.0;
}

std::vector<CanId> SampleDecoder::can_ids() const {
  std::vector<CanId> ids;
  if (mode_ != Mode::kCan) return ids;
  for (const MotorConfig& m : can_->config().motors) ids.push_back({m.can_id, m.extended});
  return ids;
}

}  // namespace inertial
