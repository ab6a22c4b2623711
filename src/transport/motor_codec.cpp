#include "inertial/transport/motor_codec.hpp"

#include <algorithm>
#include <cstdlib>
#include <cmath>
#include <fstream>
#include <set>
#include <sstream>
#include <stdexcept>

namespace inertial {
namespace {

double UintToValue(unsigned x, double lo, double hi, int bits) {
  return lo + static_cast<double>(x) * (hi - lo) / static_cast<double>((1u << bits) - 1u);
}

unsigned ValueToUint(double v, double lo, double hi, int bits) {
  const double max = static_cast<double>((1u << bits) - 1u);
  const double x = std::round((std::clamp(v, lo, hi) - lo) / (hi - lo) * max);
  return static_cast<unsigned>(std::clamp(x, 0.0, max));
}

double ReadLinear(const LinearField& f, const CanFrame& frame) {
  std::uint32_t raw = 0;
  for (int i = 0; i < f.width; ++i) {
    const std::uint8_t b = frame.data[static_cast<size_t>(f.byte + (f.little_endian ? f.width - 1 - i : i))];
    raw = (raw << 8) | b;
  }
  double v;
  if (f.is_signed) {
    const int bits = 8 * f.width;
    const std::int64_t sign = std::int64_t{1} << (bits - 1);
    std::int64_t s = static_cast<std::int64_t>(raw);
    if (s & sign) s -= sign << 1;
    v = static_cast<double>(s);
  } else {
    v = static_cast<double>(raw);
  }
  return v * f.scale + f.offset;
}

void WriteLinear(const LinearField& f, double value, CanFrame* frame) {
  const int bits = 8 * f.width;
  const double lo = f.is_signed ? -std::ldexp(1.0, bits - 1) : 0.0;
  const double hi = f.is_signed ? std::ldexp(1.0, bits - 1) - 1.0 : std::ldexp(1.0, bits) - 1.0;
  const double raw = std::clamp(std::round((value - f.offset) / f.scale), lo, hi);
  std::uint32_t u = static_cast<std::uint32_t>(static_cast<std::int64_t>(raw));
  for (int i = 0; i < f.width; ++i) {
    const int index = f.little_endian ? i : f.width - 1 - i;
    frame->data[static_cast<size_t>(f.byte + index)] = static_cast<std::uint8_t>(u & 0xFFu);
    u >>= 8;
  }
}

int Needed(const MotorConfig& m) {
  if (m.protocol == MotorProtocol::kMiniCheetah) return 6;
  return std::max({m.position.byte + m.position.width, m.velocity.byte + m.velocity.width, m.torque.byte + m.torque.width});
}

}  // namespace

Rejection DecodeMotorFrame(const MotorConfig& m, const CanFrame& f, MotorReading* r, std::string* why) {
  auto bad = [&](const std::string& reason) {
    if (why) *why = "motor " + m.joint + " (id 0x" + [&] { std::ostringstream o; o << std::hex << m.can_id; return o.str(); }() + "): " + reason;
    return Rejection::kMalformed;
  };
  if (f.remote || f.error || f.fd) return bad("a remote, error or FD frame where a reply was expected");
  if (f.length < Needed(m)) {
    return bad(std::to_string(f.length) + " data bytes, the protocol needs " + std::to_string(Needed(m)));
  }
  double p, v, t;
  if (m.protocol == MotorProtocol::kMiniCheetah) {
    const int expected = m.motor_id >= 0 ? m.motor_id : static_cast<int>(m.can_id & 0xFF);
    if (f.data[0] != expected) return bad("byte 0 is " + std::to_string(f.data[0]) + ", not the motor id " + std::to_string(expected));
    const unsigned p_int = (static_cast<unsigned>(f.data[1]) << 8) | f.data[2];
    const unsigned v_int = (static_cast<unsigned>(f.data[3]) << 4) | (f.data[4] >> 4);
    const unsigned t_int = (static_cast<unsigned>(f.data[4] & 0x0F) << 8) | f.data[5];
    p = UintToValue(p_int, m.p_min, m.p_max, 16);
    v = UintToValue(v_int, m.v_min, m.v_max, 12);
    t = UintToValue(t_int, m.t_min, m.t_max, 12);
  } else {
    p = ReadLinear(m.position, f);
    v = ReadLinear(m.velocity, f);
    t = ReadLinear(m.torque, f);
  }
  r->t = f.t;
  r->q = m.direction * p / m.gear + m.zero;
  r->qd = m.direction * v / m.gear;
  r->tau = m.direction * t * m.kt * m.gear;
  if (!std::isfinite(r->q) || !std::isfinite(r->qd) || !std::isfinite(r->tau)) return bad("a value is not finite");
  return Rejection::kNone;
}

CanFrame EncodeMotorFrame(const MotorConfig& m, const MotorReading& r) {
  CanFrame f;
  f.t = r.t;
  f.id = m.can_id;
  f.extended = m.extended;
  const double p = (r.q - m.zero) * m.gear / m.direction, v = r.qd * m.gear / m.direction,
               t = r.tau / (m.direction * m.kt * m.gear);
  if (m.protocol == MotorProtocol::kMiniCheetah) {
    const unsigned p_int = ValueToUint(p, m.p_min, m.p_max, 16), v_int = ValueToUint(v, m.v_min, m.v_max, 12),
                   t_int = ValueToUint(t, m.t_min, m.t_max, 12);
    f.length = 6;
    f.data[0] = static_cast<std::uint8_t>(m.motor_id >= 0 ? m.motor_id : static_cast<int>(m.can_id & 0xFF));
    f.data[1] = static_cast<std::uint8_t>(p_int >> 8);
    f.data[2] = static_cast<std::uint8_t>(p_int & 0xFF);
    f.data[3] = static_cast<std::uint8_t>(v_int >> 4);
    f.data[4] = static_cast<std::uint8_t>(((v_int & 0xF) << 4) | (t_int >> 8));
    f.data[5] = static_cast<std::uint8_t>(t_int & 0xFF);
  } else {
    f.length = static_cast<std::uint8_t>(std::max(8, Needed(m)));
    WriteLinear(m.position, p, &f);
    WriteLinear(m.velocity, v, &f);
    WriteLinear(m.torque, t, &f);
  }
  return f;
}

}  // namespace inertial
