/// @file option_parsing.hpp
/// Strict parsing of numeric command-line options shared by the subcommands: the error is printed
/// (naming the option and the text) and the exit code returned.
#pragma once

#include <charconv>
#include <iostream>
#include <string>
#include <type_traits>

#include "exit_codes.hpp"
#include "inertial/io/number_parsing.hpp"

namespace inertial::cli {

// Parses `text` as an integer in [lo, hi]. Returns kOk, or prints the error and returns kInvalidValue
// (not an integer) or kUsage (out of range).
template <typename T>
inline int ParseInteger(const std::string& text, const char* option, T lo, T hi, T* out) {
  if (std::is_unsigned_v<T> && text.rfind('-', 0) == 0) {
    // from_chars on an unsigned type would call "-1" not a number; it is a number out of range.
    std::cerr << "Error: " << option << ": " << text << " is out of range (" << lo << " to " << hi << ")\n";
    return kUsage;
  }
  T value{};
  const char* last = text.data() + text.size();
  const std::from_chars_result r = std::from_chars(text.data(), last, value);
  if (text.empty() || r.ptr != last || (r.ec != std::errc() && r.ec != std::errc::result_out_of_range)) {
    std::cerr << "Error: " << option << ": '" << text << "' is not an integer\n";
    return kInvalidValue;
  }
  if (r.ec == std::errc::result_out_of_range || value < lo || value > hi) {
    std::cerr << "Error: " << option << ": " << text << " is out of range (" << lo << " to " << hi << ")\n";
    return kUsage;
  }
  *out = value;
  return kOk;
}


// Parses `text` as a finite number in [lo, hi]; kOk, kInvalidValue (not a finite number) or kUsage
// (out of range), the error printed.
inline int ParseRealOption(const std::string& text, const char* option, double lo, double hi, double* out) {
  double value = 0.0;
  try {
    value = ParseDouble(text, option);
  } catch (const InvalidNumber& e) {
    std::cerr << "Error: " << e.what() << "\n";
    return kInvalidValue;
  }
  if (!(value >= lo && value <= hi)) {
    std::cerr << "Error: " << option << ": " << text << " is out of range (" << lo << " to " << hi << ")\n";
    return kUsage;
  }
  *out = value;
  return kOk;
}

}  // namespace inertial::cli
