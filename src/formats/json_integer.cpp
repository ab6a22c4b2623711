#include "inertial/formats/json_integer.hpp"

#include <cmath>

namespace inertial {
namespace {

// A whole, finite double in [lo, hi], compared as doubles before any cast. A bound near 2^63 or 2^64
// rounds up when made a double, so the callers also refuse 2^63 (2^64) and above themselves.
bool WholeWithin(double v, double lo, double hi) { return std::isfinite(v) && v == std::trunc(v) && v >= lo && v <= hi; }

}  // namespace

std::optional<std::int64_t> JsonInteger(const nlohmann::json& value, std::int64_t lo, std::int64_t hi) {
  if (value.is_number_unsigned()) {
    const std::uint64_t v = value.get<std::uint64_t>();
    if (hi < 0 || v > static_cast<std::uint64_t>(hi) || (lo > 0 && v < static_cast<std::uint64_t>(lo))) return std::nullopt;
    return static_cast<std::int64_t>(v);
  }
  if (value.is_number_integer()) {
    const std::int64_t v = value.get<std::int64_t>();
    if (v < lo || v > hi) return std::nullopt;
    return v;
  }
  if (value.is_number_float()) {
    const double v = value.get<double>();
    if (!WholeWithin(v, static_cast<double>(lo), static_cast<double>(hi)) || v >= 9223372036854775808.0) return std::nullopt;
    return static_cast<std::int64_t>(v);
  }
  return std::nullopt;
}

std::optional<std::uint64_t> JsonUnsigned(const nlohmann::json& value, std::uint64_t hi) {
  if (value.is_number_unsigned()) {
    const std::uint64_t v = value.get<std::uint64_t>();
    if (v > hi) return std::nullopt;
    return v;
  }
  if (value.is_number_integer()) return std::nullopt;  // a negative integer (non-negative ones are unsigned)
  if (value.is_number_float()) {
    const double v = value.get<double>();
    if (!WholeWithin(v, 0.0, static_cast<double>(hi)) || v >= 18446744073709551616.0) return std::nullopt;
    return static_cast<std::uint64_t>(v);
  }
  return std::nullopt;
}

std::string NotAnIntegerText(const nlohmann::json& value, std::int64_t lo, std::uint64_t hi) {
  std::string written = value.dump();
  if (written.size() > 40) written = written.substr(0, 37) + "...";
  return "is " + written + ", not an integer from " + std::to_string(lo) + " to " + std::to_string(hi);
}

}  // namespace inertial
