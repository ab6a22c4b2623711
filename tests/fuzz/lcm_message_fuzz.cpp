// Fuzz harness: LCM messages of every layout inertiald reads, as a stream into one decoder and
// estimator (the daemon's state carries from message to message: time order, the acceleration
// filter). Byte 0 chooses the layout: 0 inertial.joint_state_t, 1 a user's type described in JSON
// (tests/transport/data/leg_control_data_lcmt.json: fixed float arrays of 12 joints, no names, no time),
// 2 inertial.body_wrench_t. The rest is messages, each a 2-byte big-endian length and its bytes.
#include <fstream>

#include "fuzz_support.hpp"
#include "inertial/config/message_format.hpp"
#include "inertial/estimation/online/online_body_estimator.hpp"
#include "inertial/transport/body_message.hpp"
#include "inertial/transport/joint_message.hpp"

namespace {

const inertial::JointMessageFormat& UserFormat() {
  static const inertial::JointMessageFormat format = [] {
    std::ifstream in(std::string(InertialSourceDir()) + "/tests/transport/data/leg_control_data_lcmt.json");
    return inertial::ParseJointMessageFormat(nlohmann::json::parse(in));
  }();
  return format;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace inertial;
  if (size < 1) return 0;
  const int layout = data[0] % 3;
  std::size_t at = 1;
  std::int64_t recv_utime = 0;
  auto next = [&](const std::uint8_t** message, std::size_t* length) {
    if (at + 2 > size) return false;
    *length = std::min<std::size_t>((static_cast<std::size_t>(data[at]) << 8) | data[at + 1], size - at - 2);
    *message = data + at + 2;
    at += 2 + *length;
    recv_utime += 1000;
    return true;
  };
  const std::uint8_t* message = nullptr;
  std::size_t length = 0;
  if (layout == 2) {
    OnlineBodyEstimator e(fuzz::UnitBody());
    while (next(&message, &length)) {
      BodySample s;
      if (DecodeBodyWrench(message, length, &s) == Rejection::kNone) {
        if (!s.twist.allFinite() || !s.wrench.allFinite() || !std::isfinite(s.t)) fuzz::Fail("a decoded value is not finite");
        e.Update(s);
      }
    }
    if (!e.Body().vector().allFinite() || !CheckConsistency(e.Body()).fully_consistent()) {
      fuzz::Fail("the body estimate is not finite and consistent after body_wrench_t messages");
    }
    return 0;
  }
  JointMessageDecoder decoder(layout == 0 ? JointMessageFormat() : UserFormat(), fuzz::Leg().dof_names);
  OnlineJointEstimator e(fuzz::LegDynamics(), Eigen::VectorXd::Zero(fuzz::LegDynamics().num_parameters()));
  JointSample s;
  while (next(&message, &length)) {
    if (decoder.Decode(message, length, recv_utime, &s) == Rejection::kNone) {
      if (!s.q.allFinite() || !s.qd.allFinite() || !s.qdd.allFinite() || !s.tau.allFinite() || !std::isfinite(s.t)) {
        fuzz::Fail("a decoded value is not finite");
      }
      e.Update(s);
    }
  }
  fuzz::RequireConsistent(e, "joint messages");
  return 0;
}
