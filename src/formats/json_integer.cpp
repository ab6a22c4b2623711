#include "inertial/formats/json_integer.hpp"

#include <cmath>

namespace inertial {
namespace {

// A JSON float that is a whole number within the range of int64 (or uint64), as that integer: the
// double is compared with the type's bounds as doubles (2^63 and 2^64 are exact) before the cast,
// and the caller compares the integer with its own bounds.
std::optional<std::int64_t> WholeInt64(double v) {
  if (!std::isfinite(v) || v != std::trunc(v) || v < -9223372036854775808.0 || v >= 9223372036854775808.0) return std::nullopt;
  return static_cast<std::int64_t>(v);
}

std::optional<std::uint64_t> WholeUint64(double v) {
  if (!std::isfinite(v) || v != std::trunc(v) || v < 0.0 || v >= 18446744073709551616.0) return std::nullopt;
  return static_cast<std::uint64_t>(v);
}

}  // namespace

std::optional<std::int64_t> JsonInteger(const nlohmann::json& value, std::int64_t lo, std::int64_t hi) {
  std::optional<std::int64_t> v;
  if (value.is_number_unsigned()) {
    const std::uint64_t u = value.get<std::uint64_t>();
    if (u <= static_cast<std::uint64_t>(INT64_MAX)) v = static_cast<std::int64_t>(u);
  } else if (value.is_number_integer()) {
    v = value.get<std::int64_t>();
  } else if (value.is_number_float()) {
    v = WholeInt64(value.get<double>());
  }
  if (!v || *v < lo || *v > hi) return std::nullopt;
  return v;
}

std::optional<std::uint64_t> JsonUnsigned(const nlohmann::json& value, std::uint64_t hi) {
  std::optional<std::uint64_t> v;
  if (value.is_number_unsigned()) {
    v = value.get<std::uint64_t>();
  } else if (value.is_number_integer()) {  // signed: negative, or -0
    const std::int64_t i = value.get<std::int64_t>();
    if (i >= 0) v = static_cast<std::uint64_t>(i);
  } else if (value.is_number_float()) {
    v = WholeUint64(value.get<double>());
  }
  if (!v || *v > hi) return std::nullopt;
  return v;
}

std::string NotAnIntegerText(const nlohmann::json& value, std::int64_t lo, std::uint64_t hi) {
  // Scalars as written (strings clipped before they are written); arrays and objects by kind:
  // writing one out recurses once per level of nesting.
  std::string written;
  if (value.is_array()) {
    written = "an array";
  } else if (value.is_object()) {
    written = "an object";
  } else if (value.is_string()) {
    const std::string& s = value.get_ref<const std::string&>();
    written = nlohmann::json(s.substr(0, 40)).dump() + (s.size() > 40 ? "..." : "");
  } else {
    written = value.dump();
  }
  return "is " + written + ", not an integer from " + std::to_string(lo) + " to " + std::to_string(hi);
}

}  // namespace inertial
