#include "inertial/transport/can_joint_assembler.hpp"
#include "inertial/formats/file_error.hpp"

#include <algorithm>
#include <fstream>
#include <stdexcept>

namespace inertial {

CanJointAssembler::CanJointAssembler(CanConfig config, std::vector<std::string> dof_names)
    : config_(std::move(config)),
      dofs_(std::move(dof_names)),
      readings_(dofs_.size()) {
  for (const MotorConfig& m : config_.motors) {
    const auto it = std::find(dofs_.begin(), dofs_.end(), m.joint);
    dof_of_motor_.push_back(it == dofs_.end() ? -1 : static_cast<int>(it - dofs_.begin()));
  }
  for (const std::string& d : dofs_) {
    if (std::none_of(config_.motors.begin(), config_.motors.end(), [&](const MotorConfig& m) { return m.joint == d; })) {
      throw std::invalid_argument("CAN config: the model's joint '" + d + "' has no motor");
    }
  }
}

int CanJointAssembler::MotorOf(const CanFrame& f) const {
  for (size_t i = 0; i < config_.motors.size(); ++i) {
    const MotorConfig& m = config_.motors[i];
    if (m.can_id != f.id || m.extended != f.extended) continue;
    if (m.protocol == MotorProtocol::kMiniCheetah && f.length >= 1) {
      const int byte0 = m.motor_id >= 0 ? m.motor_id : static_cast<int>(m.can_id & 0xFF);
      // Several mini-cheetah drivers may reply on one identifier, told apart by byte 0.
      bool shared = false;
      for (size_t j = 0; j < config_.motors.size(); ++j) {
        shared = shared || (j != i && config_.motors[j].can_id == m.can_id && config_.motors[j].extended == m.extended);
      }
      if (shared && f.data[0] != byte0) continue;
    }
    return static_cast<int>(i);
  }
  return -1;
}

bool CanJointAssembler::Feed(const CanFrame& f, JointSample* s, std::string* why) {
  ++counters_.received;
  last_rejection_ = Rejection::kNone;
  auto reject = [&](Rejection r) {
    counters_.Reject(r);
    last_rejection_ = r;
  };
  if (f.error) {
    reject(Rejection::kErrorFrame);
    if (why) *why = "an error frame";
    return false;
  }
  const int motor = MotorOf(f);
  if (motor < 0 || dof_of_motor_[motor] < 0) {
    reject(Rejection::kUnknownId);
    if (why) *why = "no motor of the model replies with this frame";
    return false;
  }
  MotorReading r;
  if (DecodeMotorFrame(config_.motors[motor], f, &r, why) != Rejection::kNone) {
    reject(Rejection::kMalformed);
    return false;
  }
  const int k = dof_of_motor_[motor];
  if (readings_[k]) counters_.Reject(Rejection::kSuperseded);
  readings_[k] = r;
  bool complete = true;
  for (auto& reading : readings_) {
    if (reading && reading->t < r.t - config_.window) {
      reading.reset();
      counters_.Reject(Rejection::kLate);
    }
    complete = complete && reading.has_value();
  }
  if (!complete) return false;
  const int n = static_cast<int>(dofs_.size());
  s->t = r.t;
  s->q.resize(n);
  s->qd.resize(n);
  s->qdd.resize(n);
  s->tau.resize(n);
  for (int j = 0; j < n; ++j) {
    s->q[j] = readings_[j]->q;
    s->qd[j] = readings_[j]->qd;
    s->tau[j] = readings_[j]->tau;
    readings_[j].reset();
  }
  if (ticked_ && !(s->t > last_tick_t_)) {
    if (why) *why = "a tick not after the previous one";
    reject(Rejection::kLate);
    return false;
  }
  ticked_ = true;
  last_tick_t_ = s->t;
  s->qdd.setZero();
  s->has_qdd = false;
  s->qdd_measured = false;
  ++counters_.accepted;
  return true;
}

void WriteMotorCandump(const std::string& path, const std::string& interface, const CanConfig& config,
                       const JointSamples& samples, double stagger) {
  std::vector<int> column;
  for (const MotorConfig& m : config.motors) {
    const auto it = std::find(samples.joint_names.begin(), samples.joint_names.end(), m.joint);
    if (it == samples.joint_names.end()) throw std::invalid_argument("candump: motor joint '" + m.joint + "' is not in the log");
    column.push_back(static_cast<int>(it - samples.joint_names.begin()));
  }
  std::ofstream out(path);
  if (!out) throw std::runtime_error(CannotText("write", "candump log", path));
  for (int i = 0; i < samples.size(); ++i) {
    for (size_t k = 0; k < config.motors.size(); ++k) {
      MotorReading r;
      r.t = samples.t[i] + static_cast<double>(k) * stagger;
      r.q = samples.q(i, column[k]);
      r.qd = samples.qd(i, column[k]);
      r.tau = samples.tau(i, column[k]);
      out << FormatCandumpLine(EncodeMotorFrame(config.motors[k], r), interface) << "\n";
    }
  }
  if (!out) throw std::runtime_error(CannotText("write", "candump log", path));
}

}  // namespace inertial
