#include "inertial/model/joint_effect.hpp"
#include "inertial/model/number_text.hpp"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>

namespace inertial {
namespace {

std::string Trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return std::string(s);
}

std::vector<std::string> Split(std::string_view s, char sep) {
  std::vector<std::string> parts;
  size_t start = 0;
  while (true) {
    const size_t end = s.find(sep, start);
    parts.push_back(Trim(s.substr(start, end == std::string_view::npos ? std::string_view::npos : end - start)));
    if (end == std::string_view::npos) break;
    start = end + 1;
  }
  return parts;
}

double PositiveNumber(const std::string& item, const std::string& key, const std::string& value) {
  errno = 0;
  char* end = nullptr;
  const double x = std::strtod(value.c_str(), &end);
  if (value.empty() || end != value.c_str() + value.size() || errno != 0 || !std::isfinite(x)) {
    throw std::invalid_argument("effect '" + item + "': " + key + "='" + value + "' is not a number");
  }
  if (key != "gear" && key != "shift" && x <= 0.0) {
    throw std::invalid_argument("effect '" + item + "': " + key + " must be positive, got " + value);
  }
  if (key == "gear" && x == 0.0) throw std::invalid_argument("effect '" + item + "': gear must be non-zero");
  return x;
}

}  // namespace

std::string_view ToString(EffectKind kind) {
  switch (kind) {
    case EffectKind::kViscous: return "viscous";
    case EffectKind::kCoulomb: return "coulomb";
    case EffectKind::kOffset: return "offset";
    case EffectKind::kArmature: return "armature";
    case EffectKind::kSpring: return "spring";
    case EffectKind::kPayload: return "payload";
    case EffectKind::kRotor: return "rotor";
    case EffectKind::kAsymmetric: return "asymmetric";
    case EffectKind::kSigmoid: return "sigmoid";
    case EffectKind::kGain: return "gain";
  }
  return "unknown";
}

int NumEffectValues(EffectKind kind) {
  if (!IsJointEffect(kind)) return 0;
  return kind == EffectKind::kSpring || kind == EffectKind::kAsymmetric ? 2 : 1;
}

const std::vector<EffectKind>& AllEffectKinds() {
  static const std::vector<EffectKind> kinds{EffectKind::kViscous, EffectKind::kCoulomb,    EffectKind::kOffset,
                                             EffectKind::kArmature, EffectKind::kSpring,    EffectKind::kPayload,
                                             EffectKind::kRotor,    EffectKind::kAsymmetric, EffectKind::kSigmoid,
                                             EffectKind::kGain};
  return kinds;
}

bool IsJointEffect(EffectKind kind) { return kind != EffectKind::kPayload && kind != EffectKind::kRotor; }

bool IsMeasurementEffect(EffectKind kind) { return kind == EffectKind::kGain; }

std::string EffectItem(const EffectSpec& spec) {
  std::string item = std::string(ToString(spec.kind)) + (spec.target.empty() ? "" : "@" + spec.target);
  if (spec.kind == EffectKind::kCoulomb || spec.kind == EffectKind::kAsymmetric) {
    item += ":scale=" + FormatNumber(spec.velocity_scale, 4);
  }
  if (spec.kind == EffectKind::kSigmoid) item += ":steepness=" + FormatNumber(spec.steepness, 4) + ":shift=" + FormatNumber(spec.shift, 4);
  if (spec.kind == EffectKind::kRotor) item += ":gear=" + FormatNumber(spec.gear_ratio, 4);
  if (spec.mass > 0) item += ":mass=" + FormatNumber(spec.mass, 4);
  if (spec.radius > 0) item += ":radius=" + FormatNumber(spec.radius, 4);
  if (spec.length > 0) item += ":length=" + FormatNumber(spec.length, 4);
  return item;
}

std::vector<std::string> EffectValueNames(EffectKind kind) {
  switch (kind) {
    case EffectKind::kViscous: return {"b"};
    case EffectKind::kCoulomb: return {"bc"};
    case EffectKind::kOffset: return {"c"};
    case EffectKind::kArmature: return {"Ia"};
    case EffectKind::kSpring: return {"k", "q0"};
    case EffectKind::kAsymmetric: return {"bp", "bn"};
    case EffectKind::kSigmoid: return {"p1"};
    case EffectKind::kGain: return {"g"};
    default: return {};
  }
}

double SigmoidFriction(double qd, double steepness, double shift) {
  // S(x) = (1 + tanh(x / 2)) / 2: no exponential to overflow.
  return 0.5 * (std::tanh(0.5 * steepness * (qd + shift)) - std::tanh(0.5 * steepness * shift));
}

double VelocityEffectTorque(const EffectSpec& spec, const std::vector<double>& values, double qd) {
  if (static_cast<int>(values.size()) != NumEffectValues(spec.kind)) return std::nan("");
  switch (spec.kind) {
    case EffectKind::kViscous: return values[0] * qd;
    case EffectKind::kCoulomb: return values[0] * std::tanh(qd / spec.velocity_scale);
    case EffectKind::kAsymmetric: {
      const double s = std::tanh(qd / spec.velocity_scale);
      return s >= 0.0 ? values[0] * s : values[1] * s;
    }
    case EffectKind::kSigmoid: return values[0] * SigmoidFriction(qd, spec.steepness, spec.shift);
    case EffectKind::kOffset: return values[0];
    default: return std::nan("");
  }
}

std::vector<EffectSpec> ParseEffectList(std::string_view text) {
  std::vector<EffectSpec> effects;
  const std::string all = Trim(text);
  if (all.empty()) return effects;
  for (const std::string& item : Split(all, ',')) {
    if (item.empty()) throw std::invalid_argument("effects '" + all + "': empty item (two commas in a row?)");
    const std::vector<std::string> fields = Split(item, ':');
    EffectSpec e;
    e.text = item;
    const std::string& head = fields[0];
    const size_t at = head.find('@');
    const std::string kind = Trim(head.substr(0, at));
    if (at != std::string::npos) {
      e.target = Trim(head.substr(at + 1));
      if (e.target.empty()) throw std::invalid_argument("effect '" + item + "': empty target after '@'");
    }
    bool known = false;
    for (EffectKind k : AllEffectKinds()) {
      if (kind == ToString(k)) {
        e.kind = k;
        known = true;
      }
    }
    if (!known) {
      throw std::invalid_argument("effect '" + item + "': unknown kind '" + kind +
                                  "' (known: viscous, coulomb, asymmetric, sigmoid, offset, armature, spring, payload, rotor)");
    }
    if (!IsJointEffect(e.kind) && e.target.empty()) {
      throw std::invalid_argument("effect '" + item + "': " + kind + " needs a target, e.g. " + kind +
                                  (e.kind == EffectKind::kPayload ? "@tool0" : "@knee:gear=9"));
    }
    for (size_t f = 1; f < fields.size(); ++f) {
      const size_t eq = fields[f].find('=');
      if (eq == std::string::npos) {
        throw std::invalid_argument("effect '" + item + "': option '" + fields[f] + "' is not key=value");
      }
      const std::string key = Trim(fields[f].substr(0, eq));
      const std::string value = Trim(fields[f].substr(eq + 1));
      const bool ok = ((e.kind == EffectKind::kCoulomb || e.kind == EffectKind::kAsymmetric) && key == "scale") ||
                      (e.kind == EffectKind::kSigmoid && (key == "steepness" || key == "shift")) ||
                      (e.kind == EffectKind::kRotor && (key == "gear" || key == "mass" || key == "radius" || key == "length")) ||
                      (e.kind == EffectKind::kPayload && (key == "mass" || key == "radius"));
      if (!ok) throw std::invalid_argument("effect '" + item + "': unknown option '" + key + "' for " + kind);
      const double x = PositiveNumber(item, key, value);
      if (key == "scale") e.velocity_scale = x;
      if (key == "gear") e.gear_ratio = x;
      if (key == "mass") e.mass = x;
      if (key == "radius") e.radius = x;
      if (key == "length") e.length = x;
      if (key == "steepness") e.steepness = x;
      if (key == "shift") e.shift = x;
    }
    if (e.kind == EffectKind::kRotor && e.gear_ratio == 0.0) {
      throw std::invalid_argument("effect '" + item + "': a rotor needs its gear ratio, e.g. rotor@" + e.target +
                                  ":gear=9");
    }
    effects.push_back(e);
  }
  return effects;
}

}  // namespace inertial
