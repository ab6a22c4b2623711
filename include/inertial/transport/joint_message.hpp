/// @file joint_message.hpp
/// Joint-state messages (LCM) into joint-space samples of a model, for inertiald and replay:
/// the project's inertial.joint_state_t, or a user's own message type described by a format (its
/// layout and which fields are q, qd, qdd, tau, the time and the joint names), e.g. for MIT
/// Cheetah-style leg_control_data_lcmt: {"layout": {...}, "joint_names": [...], "q": "q",
/// "qd": "qd", "tau": "tau_est"}. Every message is decoded by lcm_layout.hpp (nothing trusted) and
/// mapped by joint name onto the model's DOFs. A message without accelerations gives a sample with
/// has_qdd false: deriving qdd is the preprocessing stage's (stream_preprocessor.hpp), at the
/// format's accel_cutoff_hz; the decoder only decodes.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "inertial/signal/rejection.hpp"
#include "inertial/transport/lcm_layout.hpp"
#include "inertial/model/joint_samples.hpp"

namespace inertial {

/// The layout of inertial.joint_state_t (lcmtypes/joint_state_t.lcm).
const LcmLayout& JointStateLayout();

struct JointMessageFormat {
  LcmLayout layout = JointStateLayout();
  std::string utime_field = "utime";  ///< microseconds; empty: the receive time
  std::string names_field = "joint_names";  ///< a string array; empty: joint_names below
  std::vector<std::string> joint_names;     ///< the order of the arrays when names_field is empty
  std::string q = "q", qd = "qd", qdd = "qdd", tau = "tau";  ///< qdd empty: derived
  double accel_cutoff_hz = 20.0;  ///< for the preprocessing stage, when qdd is not in the messages
};

class JointMessageDecoder {
 public:
  /// @throws std::invalid_argument if the format's fields are not in its layout or a DOF has no
  /// name in a fixed joint_names list.
  JointMessageDecoder(JointMessageFormat format, std::vector<std::string> dof_names);

  /// Decodes one message into *sample (sized for the model once; reused). recv_utime is used when
  /// the format has no time field. Rejection::kNone, or kDecode, kWrongSize, kUnknownJoint,
  /// kNonFinite (rejection.hpp); on rejection *why (optional) says what is wrong.
  Rejection Decode(const void* data, std::size_t size, std::int64_t recv_utime, JointSample* sample,
                          std::string* why = nullptr);

  const JointMessageFormat& format() const { return format_; }
  int num_dofs() const { return static_cast<int>(dofs_.size()); }

 private:
  JointMessageFormat format_;
  std::vector<std::string> dofs_;
  std::uint64_t fingerprint_ = 0;  // of format_.layout, once
  LcmRecord record_;               // reused: nothing allocated per message once the arrays have their size
};

/// Encodes a sample as inertial.joint_state_t (names in the sample's DOF order, utime = t * 1e6).
std::vector<std::uint8_t> EncodeJointState(const std::vector<std::string>& names, const JointSample& sample,
                                           bool with_qdd = true);

/// Writes every sample of a joint log as an LCM log (lcm::LogFile, as lcm-logger writes) of
/// inertial.joint_state_t on `channel`, event time stamps = sample times.
/// @throws std::runtime_error if the file cannot be written.
void WriteJointStateLog(const std::string& path, const std::string& channel, const JointSamples& samples,
                        bool with_qdd = true);

}  // namespace inertial
