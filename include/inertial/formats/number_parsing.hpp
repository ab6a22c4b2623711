/// @file number_parsing.hpp
/// Strict parsing of numbers from text (command lines, stdin, files): the whole token must be a
/// number, finite unless allowed. Errors name the input and what is wrong.
#pragma once

#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace inertial {

/// A value that is not a valid number, or not finite.
class InvalidNumber : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

/// Parses one decimal floating-point number ("1", "-2.5e-3", "inf" only if allow_non_finite).
/// @throws InvalidNumber "<what>: '<text>' is not a number" / "... is not finite" / "... out of range".
double ParseDouble(std::string_view text, std::string_view what, bool allow_non_finite = false);

/// Splits on whitespace and commas and parses every token; `what` names the input in errors, each
/// token as "<what>, value N".
std::vector<double> ParseNumberList(std::string_view text, std::string_view what);

}  // namespace inertial
