#include "inertial/transport/joint_message.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <lcm/lcm-cpp.hpp>

#include "inertial/formats/file_error.hpp"
#include "inertial/joint_state_t.hpp"

namespace inertial {
namespace {

LcmField Field(const char* name, LcmType type, const char* length_field = "") {
  LcmField f;
  f.name = name;
  f.type = type;
  f.length_field = length_field;
  return f;
}

bool HasField(const LcmLayout& layout, const std::string& name, bool want_string) {
  for (const LcmField& f : layout.fields) {
    if (f.name == name) return (f.type == LcmType::kString) == want_string;
  }
  return false;
}

}  // namespace

const LcmLayout& JointStateLayout() {
  static const LcmLayout layout{"inertial.joint_state_t",
                                {Field("utime", LcmType::kInt64), Field("num_joints", LcmType::kInt32),
                                 Field("joint_names", LcmType::kString, "num_joints"),
                                 Field("q", LcmType::kDouble, "num_joints"), Field("qd", LcmType::kDouble, "num_joints"),
                                 Field("num_qdd", LcmType::kInt32), Field("qdd", LcmType::kDouble, "num_qdd"),
                                 Field("tau", LcmType::kDouble, "num_joints")}};
  return layout;
}

JointMessageDecoder::JointMessageDecoder(JointMessageFormat format, std::vector<std::string> dof_names)
    : format_(std::move(format)),
      dofs_(std::move(dof_names)) {
  fingerprint_ = LcmFingerprint(format_.layout);  // checks the layout
  for (const std::string* name : {&format_.q, &format_.qd, &format_.tau}) {
    if (name->empty() || !HasField(format_.layout, *name, false)) {
      throw std::invalid_argument("message format: q, qd and tau must name numeric fields of the layout ('" + *name +
                                  "' is not one)");
    }
  }
  if (!format_.qdd.empty() && !HasField(format_.layout, format_.qdd, false)) {
    throw std::invalid_argument("message format: qdd '" + format_.qdd + "' is not a numeric field of the layout");
  }
  if (!format_.utime_field.empty() && !HasField(format_.layout, format_.utime_field, false)) {
    throw std::invalid_argument("message format: utime '" + format_.utime_field + "' is not a numeric field");
  }
  for (const LcmField& f : format_.layout.fields) {
    if (f.name == format_.utime_field && f.is_array()) {
      throw std::invalid_argument("message format: utime '" + f.name + "' must be a scalar field, not an array");
    }
  }
  if (!format_.names_field.empty() && !HasField(format_.layout, format_.names_field, true)) {
    throw std::invalid_argument("message format: names '" + format_.names_field + "' is not a string field");
  }
  if (format_.names_field.empty()) {
    for (const std::string& d : dofs_) {
      if (std::find(format_.joint_names.begin(), format_.joint_names.end(), d) == format_.joint_names.end()) {
        throw std::invalid_argument("message format: the model's joint '" + d + "' is not in joint_names");
      }
    }
  }
}

Rejection JointMessageDecoder::Decode(const void* data, std::size_t size, std::int64_t recv_utime, JointSample* s,
                                      std::string* why) {
  const int n = num_dofs();
  LcmRecord& r = record_;
  try {
    DecodeLcmInto(format_.layout, fingerprint_, data, size, &r);
  } catch (const LcmDecodeError& e) {
    if (why) *why = e.what();
    return Rejection::kDecode;
  }
  const std::vector<std::string>& names = format_.names_field.empty() ? format_.joint_names : r.strings[format_.names_field];
  const std::vector<double>& q = r.numbers[format_.q];
  const std::vector<double>& qd = r.numbers[format_.qd];
  const std::vector<double>& tau = r.numbers[format_.tau];
  const std::vector<double>* qdd = format_.qdd.empty() ? nullptr : &r.numbers[format_.qdd];
  const bool has_qdd = qdd != nullptr && !qdd->empty();
  const size_t m = names.size();
  if (q.size() != m || qd.size() != m || tau.size() != m || (has_qdd && qdd->size() != m)) {
    if (why) {
      *why = std::to_string(m) + " joint names but q, qd, tau" + std::string(has_qdd ? ", qdd" : "") + " have " +
             std::to_string(q.size()) + ", " + std::to_string(qd.size()) + ", " + std::to_string(tau.size()) +
             (has_qdd ? ", " + std::to_string(qdd->size()) : "") + " values";
    }
    return Rejection::kWrongSize;
  }
  s->q.resize(n);
  s->qd.resize(n);
  s->qdd.resize(n);
  s->tau.resize(n);
  std::vector<bool> filled(n, false);
  for (size_t i = 0; i < m; ++i) {
    const auto it = std::find(dofs_.begin(), dofs_.end(), names[i]);
    if (it == dofs_.end()) {
      if (!format_.names_field.empty()) {
        if (why) *why = "joint '" + names[i] + "' is not in the model";
        return Rejection::kUnknownJoint;
      }
      continue;  // a fixed list may hold joints the model does not use
    }
    const int k = static_cast<int>(it - dofs_.begin());
    if (filled[k]) {
      if (why) *why = "joint '" + names[i] + "' appears twice";
      return Rejection::kWrongSize;
    }
    filled[k] = true;
    s->q[k] = q[i];
    s->qd[k] = qd[i];
    s->tau[k] = tau[i];
    if (has_qdd) s->qdd[k] = (*qdd)[i];
  }
  for (int k = 0; k < n; ++k) {
    if (!filled[k]) {
      if (why) *why = "the model's joint '" + dofs_[k] + "' is missing";
      return Rejection::kWrongSize;
    }
  }
  const double utime = format_.utime_field.empty() ? static_cast<double>(recv_utime) : r.numbers[format_.utime_field][0];
  s->t = utime * 1e-6;
  if (!std::isfinite(s->t) || !s->q.allFinite() || !s->qd.allFinite() || !s->tau.allFinite() ||
      (has_qdd && !s->qdd.allFinite())) {
    if (why) *why = "a value is not finite";
    return Rejection::kNonFinite;
  }
  s->has_qdd = has_qdd;
  s->qdd_measured = has_qdd;
  if (!has_qdd) s->qdd.setZero();
  return Rejection::kNone;
}

std::vector<std::uint8_t> EncodeJointState(const std::vector<std::string>& names, const JointSample& s, bool with_qdd) {
  inertial::joint_state_t m;
  m.utime = static_cast<std::int64_t>(std::llround(s.t * 1e6));
  m.num_joints = static_cast<std::int32_t>(names.size());
  m.joint_names = names;
  m.q.assign(s.q.data(), s.q.data() + s.q.size());
  m.qd.assign(s.qd.data(), s.qd.data() + s.qd.size());
  m.num_qdd = with_qdd ? m.num_joints : 0;
  if (with_qdd) m.qdd.assign(s.qdd.data(), s.qdd.data() + s.qdd.size());
  m.tau.assign(s.tau.data(), s.tau.data() + s.tau.size());
  std::vector<std::uint8_t> buffer(static_cast<size_t>(m.getEncodedSize()));
  m.encode(buffer.data(), 0, static_cast<int>(buffer.size()));
  return buffer;
}

void WriteJointStateLog(const std::string& path, const std::string& channel, const JointSamples& samples,
                        bool with_qdd) {
  lcm::LogFile log(path, "w");
  if (!log.good()) throw std::runtime_error(CannotText("write", "LCM log", path));
  JointSample s;
  for (int i = 0; i < samples.size(); ++i) {
    CopySample(samples, i, &s);
    std::vector<std::uint8_t> bytes = EncodeJointState(samples.joint_names, s, with_qdd);
    lcm::LogEvent ev;
    ev.eventnum = i;
    ev.timestamp = static_cast<std::int64_t>(std::llround(s.t * 1e6));
    ev.channel = channel;
    ev.datalen = static_cast<std::int32_t>(bytes.size());
    ev.data = bytes.data();
    if (log.writeEvent(&ev) != 0) throw std::runtime_error(CannotText("write", "LCM log", path));
  }
}

}  // namespace inertial
