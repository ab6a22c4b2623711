/// @file json_integer.hpp
/// An integer read from JSON (versions, counters, sizes in checkpoints and in inertiald's config)
/// checked as an integer in range before any conversion: nlohmann's get<int>() on 1e308 is
/// undefined behaviour and on 1.9 truncates to 1 (issue 35). A JSON number is accepted when it is an
/// integer, or a float whose value is a whole number (JSON does not tell 2 from 2.0, and Python
/// writes 2.0), within [lo, hi].
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

namespace inertial {

/// The value as an integer in [lo, hi], or nullopt if it is not a number, not whole, or out of range.
std::optional<std::int64_t> JsonInteger(const nlohmann::json& value, std::int64_t lo, std::int64_t hi);

/// The same for unsigned counters, in [0, hi].
std::optional<std::uint64_t> JsonUnsigned(const nlohmann::json& value, std::uint64_t hi);

/// "is 1.9, not an integer from 1 to 100000" (the value as written, clipped to 40 characters).
std::string NotAnIntegerText(const nlohmann::json& value, std::int64_t lo, std::uint64_t hi);

}  // namespace inertial
