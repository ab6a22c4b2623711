#include "inertial/io/motor_codec.hpp"

#include <yaml-cpp/yaml.h>

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

FrameRejection DecodeMotorFrame(const MotorConfig& m, const CanFrame& f, MotorReading* r, std::string* why) {
  auto bad = [&](const std::string& reason) {
    if (why) *why = "motor " + m.joint + " (id 0x" + [&] { std::ostringstream o; o << std::hex << m.can_id; return o.str(); }() + "): " + reason;
    return FrameRejection::kMalformed;
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
  return FrameRejection::kNone;
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

namespace {
CanConfig ParseCanConfigNodes(const std::string& text, const std::string& source);
}  // namespace

CanConfig ParseCanConfig(const std::string& text, const std::string& source) {
  try {
    return ParseCanConfigNodes(text, source);
  } catch (const YAML::Exception& e) {  // a value of the wrong kind (a list where a number belongs ...)
    throw std::invalid_argument(source + ": " + e.what());
  }
}

namespace {

// An integer field: finite, whole and within [lo, hi] before any cast.
int Integer(const YAML::Node& n, const std::string& where, double lo, double hi, const std::string& source) {
  double v = 0.0;
  try {
    v = n.as<double>();
  } catch (const YAML::Exception&) {
    throw std::invalid_argument(source + ": " + where + " must be an integer");
  }
  if (!std::isfinite(v) || v != std::floor(v) || v < lo || v > hi) {
    throw std::invalid_argument(source + ": " + where + " must be an integer in [" + std::to_string(static_cast<long long>(lo)) +
                                ", " + std::to_string(static_cast<long long>(hi)) + "]");
  }
  return static_cast<int>(v);
}

CanConfig ParseCanConfigNodes(const std::string& text, const std::string& source) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw std::invalid_argument(source + ": not valid YAML: " + e.what());
  }
  if (!root.IsMap()) throw std::invalid_argument(source + ": expected a mapping with 'motors'");
  CanConfig c;
  auto number = [&](const YAML::Node& n, const std::string& where) {
    try {
      const double v = n.as<double>();
      if (!std::isfinite(v)) throw std::invalid_argument("");
      return v;
    } catch (...) {
      throw std::invalid_argument(source + ": " + where + " must be a finite number");
    }
  };
  for (const auto& kv : root) {
    const std::string key = kv.first.as<std::string>();
    if (key != "window" && key != "accel_cutoff_hz" && key != "motors") {
      throw std::invalid_argument(source + ": unknown key '" + key + "' (window, accel_cutoff_hz, motors)");
    }
  }
  if (root["window"]) c.window = number(root["window"], "window");
  if (root["accel_cutoff_hz"]) c.accel_cutoff_hz = number(root["accel_cutoff_hz"], "accel_cutoff_hz");
  if (!(c.window > 0) || !(c.accel_cutoff_hz > 0)) throw std::invalid_argument(source + ": window and accel_cutoff_hz must be positive");
  if (!root["motors"] || !root["motors"].IsSequence() || root["motors"].size() == 0) {
    throw std::invalid_argument(source + ": 'motors' must be a non-empty list");
  }
  std::set<std::pair<std::uint32_t, int>> frames;
  std::set<std::string> joints;
  int index = 0;
  for (const YAML::Node& n : root["motors"]) {
    const std::string where = "motor " + std::to_string(index++);
    if (!n.IsMap()) throw std::invalid_argument(source + ": " + where + " must be a mapping");
    static const std::set<std::string> kKeys{"id", "extended", "motor_id", "joint", "protocol", "position", "velocity",
                                             "torque", "gear", "kt", "direction", "zero"};
    for (const auto& kv : n) {
      if (kKeys.count(kv.first.as<std::string>()) == 0) {
        throw std::invalid_argument(source + ": " + where + ": unknown key '" + kv.first.as<std::string>() + "'");
      }
    }
    MotorConfig m;
    if (!n["id"] || !n["joint"]) throw std::invalid_argument(source + ": " + where + " needs 'id' and 'joint'");
    m.joint = n["joint"].as<std::string>();
    const std::string w = source + ": motor '" + m.joint + "'";
    // Identifiers are usually written in hex (0x141): parsed with base prefixes.
    const std::string id_text = n["id"].as<std::string>();
    char* end = nullptr;
    const double id = static_cast<double>(std::strtoll(id_text.c_str(), &end, 0));
    if (id_text.empty() || end == nullptr || *end != '\0') {
      throw std::invalid_argument(source + ": " + where + ": id '" + id_text + "' is not an integer");
    }
    m.extended = n["extended"] && n["extended"].as<bool>();
    if (id < 0 || id > (m.extended ? 0x1FFFFFFF : 0x7FF) || id != std::floor(id)) {
      throw std::invalid_argument(w + ": id " + n["id"].as<std::string>() + " is not a valid " +
                                  (m.extended ? "29" : "11") + "-bit CAN identifier");
    }
    m.can_id = static_cast<std::uint32_t>(id);
    if (n["motor_id"]) m.motor_id = Integer(n["motor_id"], where + " motor_id", 0, 255, source);
    const std::string protocol = n["protocol"] ? n["protocol"].as<std::string>() : "mini_cheetah";
    if (protocol == "mini_cheetah") {
      m.protocol = MotorProtocol::kMiniCheetah;
      auto range = [&](const char* key, double* lo, double* hi) {
        if (!n[key]) return;
        if (!n[key].IsSequence() || n[key].size() != 2) throw std::invalid_argument(w + ": " + key + " must be [min, max]");
        *lo = number(n[key][0], where + " " + key);
        *hi = number(n[key][1], where + " " + key);
        if (!(*hi > *lo)) throw std::invalid_argument(w + ": " + key + " needs min < max");
      };
      range("position", &m.p_min, &m.p_max);
      range("velocity", &m.v_min, &m.v_max);
      range("torque", &m.t_min, &m.t_max);
    } else if (protocol == "linear") {
      m.protocol = MotorProtocol::kLinear;
      auto field = [&](const char* key, LinearField* f) {
        const YAML::Node& x = n[key];
        if (!x || !x.IsMap()) throw std::invalid_argument(w + ": linear protocol needs '" + key + "': {byte, width, ...}");
        f->byte = x["byte"] ? Integer(x["byte"], where + " " + key + ".byte", 0, 7, source) : 0;
        f->width = x["width"] ? Integer(x["width"], where + " " + key + ".width", 1, 4, source) : 2;
        f->is_signed = !x["signed"] || x["signed"].as<bool>();
        const std::string endian = x["endian"] ? x["endian"].as<std::string>() : "little";
        if (endian != "little" && endian != "big") throw std::invalid_argument(w + ": " + key + ".endian must be little or big");
        f->little_endian = endian == "little";
        f->scale = x["scale"] ? number(x["scale"], where + " " + key + ".scale") : 1.0;
        f->offset = x["offset"] ? number(x["offset"], where + " " + key + ".offset") : 0.0;
        if (f->width != 1 && f->width != 2 && f->width != 4) throw std::invalid_argument(w + ": " + key + ".width must be 1, 2 or 4");
        if (f->byte + f->width > 8) throw std::invalid_argument(w + ": " + key + " lies outside the 8 data bytes of a reply");
        if (f->scale == 0.0) throw std::invalid_argument(w + ": " + key + ".scale must not be 0");
      };
      field("position", &m.position);
      field("velocity", &m.velocity);
      field("torque", &m.torque);
    } else {
      throw std::invalid_argument(w + ": protocol '" + protocol + "' is not mini_cheetah or linear");
    }
    if (n["gear"]) m.gear = number(n["gear"], where + " gear");
    if (n["kt"]) m.kt = number(n["kt"], where + " kt");
    if (n["direction"]) m.direction = number(n["direction"], where + " direction");
    if (n["zero"]) m.zero = number(n["zero"], where + " zero");
    if (m.gear == 0.0 || m.kt == 0.0 || (m.direction != 1.0 && m.direction != -1.0)) {
      throw std::invalid_argument(w + ": gear and kt must be non-zero and direction 1 or -1");
    }
    const int byte0 = m.protocol == MotorProtocol::kMiniCheetah ? (m.motor_id >= 0 ? m.motor_id : static_cast<int>(m.can_id & 0xFF)) : -1;
    if (!frames.insert({m.can_id | (m.extended ? 0x80000000u : 0u), byte0}).second) {
      throw std::invalid_argument(w + ": another motor already replies with these frames");
    }
    if (!joints.insert(m.joint).second) throw std::invalid_argument(w + ": joint '" + m.joint + "' has two motors");
    c.motors.push_back(m);
  }
  return c;
}

}  // namespace

CanConfig LoadCanConfig(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot open '" + path + "'");
  std::stringstream s;
  s << in.rdbuf();
  return ParseCanConfig(s.str(), path);
}

}  // namespace inertial
