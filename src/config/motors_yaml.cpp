#include "inertial/config/motors_yaml.hpp"
#include "inertial/formats/input_file.hpp"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <set>
#include <stdexcept>

namespace inertial {

namespace {
CanConfig ParseCanConfigNodes(const std::string& text, const std::string& source);
}  // namespace

CanConfig ParseCanConfig(const std::string& text, const std::string& source) {
  if (text.size() > kMaxSettingsFileBytes) {
    throw std::invalid_argument(TooLargeText(source, "motor configuration", text.size(), kMaxSettingsFileBytes));
  }
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

// A real-number field: finite.
double Number(const YAML::Node& n, const std::string& where, const std::string& source) {
  try {
    const double v = n.as<double>();
    if (!std::isfinite(v)) throw std::invalid_argument("");
    return v;
  } catch (...) {
    throw std::invalid_argument(source + ": " + where + " must be a finite number");
  }
}

// Rejects a key of a motor's mapping that is not one of the known ones.
void CheckMotorKeys(const YAML::Node& n, const std::string& where, const std::string& source) {
  static const std::set<std::string> kKeys{"id", "extended", "motor_id", "joint", "protocol", "position", "velocity",
                                           "torque", "gear", "kt", "direction", "zero"};
  for (const auto& kv : n) {
    if (kKeys.count(kv.first.as<std::string>()) == 0) {
      throw std::invalid_argument(source + ": " + where + ": unknown key '" + kv.first.as<std::string>() + "'");
    }
  }
}

// Reads the CAN identifier ('id', usually hex such as 0x141, parsed with base prefixes) and
// 'extended' into m; w names the motor by its joint.
void ReadCanId(const YAML::Node& n, const std::string& where, const std::string& w, const std::string& source,
               MotorConfig& m) {
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
}

// Reads an optional [min, max] range of the mini_cheetah protocol (left as it is when absent).
void ReadRange(const YAML::Node& n, const char* key, const std::string& where, const std::string& w,
               const std::string& source, double* lo, double* hi) {
  if (!n[key]) return;
  if (!n[key].IsSequence() || n[key].size() != 2) throw std::invalid_argument(w + ": " + key + " must be [min, max]");
  *lo = Number(n[key][0], where + " " + key, source);
  *hi = Number(n[key][1], where + " " + key, source);
  if (!(*hi > *lo)) throw std::invalid_argument(w + ": " + key + " needs min < max");
}

// Reads one field of the linear protocol ({byte, width, signed, endian, scale, offset}), required.
void ReadLinearField(const YAML::Node& n, const char* key, const std::string& where, const std::string& w,
                     const std::string& source, LinearField* f) {
  const YAML::Node& x = n[key];
  if (!x || !x.IsMap()) throw std::invalid_argument(w + ": linear protocol needs '" + key + "': {byte, width, ...}");
  f->byte = x["byte"] ? Integer(x["byte"], where + " " + key + ".byte", 0, 7, source) : 0;
  f->width = x["width"] ? Integer(x["width"], where + " " + key + ".width", 1, 4, source) : 2;
  f->is_signed = !x["signed"] || x["signed"].as<bool>();
  const std::string endian = x["endian"] ? x["endian"].as<std::string>() : "little";
  if (endian != "little" && endian != "big") throw std::invalid_argument(w + ": " + key + ".endian must be little or big");
  f->little_endian = endian == "little";
  f->scale = x["scale"] ? Number(x["scale"], where + " " + key + ".scale", source) : 1.0;
  f->offset = x["offset"] ? Number(x["offset"], where + " " + key + ".offset", source) : 0.0;
  if (f->width != 1 && f->width != 2 && f->width != 4) throw std::invalid_argument(w + ": " + key + ".width must be 1, 2 or 4");
  if (f->byte + f->width > 8) throw std::invalid_argument(w + ": " + key + " lies outside the 8 data bytes of a reply");
  if (f->scale == 0.0) throw std::invalid_argument(w + ": " + key + ".scale must not be 0");
}

// Reads one entry of 'motors' (named "motor <index>" in errors until its joint is known).
MotorConfig ParseMotor(const YAML::Node& n, const std::string& where, const std::string& source) {
  if (!n.IsMap()) throw std::invalid_argument(source + ": " + where + " must be a mapping");
  CheckMotorKeys(n, where, source);
  MotorConfig m;
  if (!n["id"] || !n["joint"]) throw std::invalid_argument(source + ": " + where + " needs 'id' and 'joint'");
  m.joint = n["joint"].as<std::string>();
  const std::string w = source + ": motor '" + m.joint + "'";
  ReadCanId(n, where, w, source, m);
  if (n["motor_id"]) m.motor_id = Integer(n["motor_id"], where + " motor_id", 0, 255, source);
  const std::string protocol = n["protocol"] ? n["protocol"].as<std::string>() : "mini_cheetah";
  if (protocol == "mini_cheetah") {
    m.protocol = MotorProtocol::kMiniCheetah;
    ReadRange(n, "position", where, w, source, &m.p_min, &m.p_max);
    ReadRange(n, "velocity", where, w, source, &m.v_min, &m.v_max);
    ReadRange(n, "torque", where, w, source, &m.t_min, &m.t_max);
  } else if (protocol == "linear") {
    m.protocol = MotorProtocol::kLinear;
    ReadLinearField(n, "position", where, w, source, &m.position);
    ReadLinearField(n, "velocity", where, w, source, &m.velocity);
    ReadLinearField(n, "torque", where, w, source, &m.torque);
  } else {
    throw std::invalid_argument(w + ": protocol '" + protocol + "' is not mini_cheetah or linear");
  }
  if (n["gear"]) m.gear = Number(n["gear"], where + " gear", source);
  if (n["kt"]) m.kt = Number(n["kt"], where + " kt", source);
  if (n["direction"]) m.direction = Number(n["direction"], where + " direction", source);
  if (n["zero"]) m.zero = Number(n["zero"], where + " zero", source);
  if (m.gear == 0.0 || m.kt == 0.0 || (m.direction != 1.0 && m.direction != -1.0)) {
    throw std::invalid_argument(w + ": gear and kt must be non-zero and direction 1 or -1");
  }
  return m;
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
  for (const auto& kv : root) {
    const std::string key = kv.first.as<std::string>();
    if (key != "window" && key != "accel_cutoff_hz" && key != "motors") {
      throw std::invalid_argument(source + ": unknown key '" + key + "' (window, accel_cutoff_hz, motors)");
    }
  }
  if (root["window"]) c.window = Number(root["window"], "window", source);
  if (root["accel_cutoff_hz"]) c.accel_cutoff_hz = Number(root["accel_cutoff_hz"], "accel_cutoff_hz", source);
  if (!(c.window > 0) || !(c.accel_cutoff_hz > 0)) throw std::invalid_argument(source + ": window and accel_cutoff_hz must be positive");
  if (!root["motors"] || !root["motors"].IsSequence() || root["motors"].size() == 0) {
    throw std::invalid_argument(source + ": 'motors' must be a non-empty list");
  }
  std::set<std::pair<std::uint32_t, int>> frames;
  std::set<std::string> joints;
  int index = 0;
  for (const YAML::Node& n : root["motors"]) {
    const MotorConfig m = ParseMotor(n, "motor " + std::to_string(index++), source);
    const std::string w = source + ": motor '" + m.joint + "'";
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
  std::string text;
  try {
    text = ReadInputFile(path, "motor configuration", kMaxSettingsFileBytes);
  } catch (const InputFileError& e) {
    if (e.reason() == InputFileError::Reason::kTooLarge) throw std::invalid_argument(e.what());
    throw std::runtime_error(e.what());
  }
  return ParseCanConfig(text, path);
}

}  // namespace inertial
