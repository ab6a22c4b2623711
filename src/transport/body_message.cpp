#include "inertial/transport/body_message.hpp"

#include <cmath>

#include "inertial/body_wrench_t.hpp"

namespace inertial {
namespace {

LcmField Field(const char* name, LcmType type, int length = -1) {
  LcmField f;
  f.name = name;
  f.type = type;
  f.length = length;
  return f;
}

}  // namespace

const LcmLayout& BodyWrenchLayout() {
  static const LcmLayout layout{"inertial.body_wrench_t",
                                {Field("utime", LcmType::kInt64), Field("frame", LcmType::kString),
                                 Field("has_twist", LcmType::kBoolean), Field("twist", LcmType::kDouble, 6),
                                 Field("has_acceleration", LcmType::kBoolean), Field("acceleration", LcmType::kDouble, 6),
                                 Field("wrench", LcmType::kDouble, 6), Field("gravity", LcmType::kDouble, 3)}};
  return layout;
}

Rejection DecodeBodyWrench(const void* data, std::size_t size, BodySample* s, std::string* why) {
  LcmRecord r;
  try {
    r = DecodeLcm(BodyWrenchLayout(), data, size);
  } catch (const LcmDecodeError& e) {
    if (why) *why = e.what();
    return Rejection::kDecode;
  }
  if (r.numbers["has_twist"][0] == 0.0) {
    if (why) *why = "no twist (has_twist false)";
    return Rejection::kWrongSize;
  }
  s->t = r.numbers["utime"][0] * 1e-6;
  for (int i = 0; i < 6; ++i) {
    s->twist[i] = r.numbers["twist"][i];
    s->acceleration[i] = r.numbers["acceleration"][i];
    s->wrench[i] = r.numbers["wrench"][i];
  }
  for (int i = 0; i < 3; ++i) s->gravity[i] = r.numbers["gravity"][i];
  s->has_acceleration = r.numbers["has_acceleration"][0] != 0.0;
  if (!std::isfinite(s->t) || !s->twist.allFinite() || !s->wrench.allFinite() || !s->gravity.allFinite() ||
      (s->has_acceleration && !s->acceleration.allFinite())) {
    if (why) *why = "a value is not finite";
    return Rejection::kNonFinite;
  }
  return Rejection::kNone;
}

std::vector<std::uint8_t> EncodeBodyWrench(const BodySample& s, const std::string& frame) {
  inertial::body_wrench_t m;
  m.utime = static_cast<std::int64_t>(std::llround(s.t * 1e6));
  m.frame = frame;
  m.has_twist = true;
  m.has_acceleration = s.has_acceleration;
  for (int i = 0; i < 6; ++i) {
    m.twist[i] = s.twist[i];
    m.acceleration[i] = s.acceleration[i];
    m.wrench[i] = s.wrench[i];
  }
  for (int i = 0; i < 3; ++i) m.gravity[i] = s.gravity[i];
  std::vector<std::uint8_t> bytes(static_cast<size_t>(m.getEncodedSize()));
  m.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
  return bytes;
}

}  // namespace inertial
