/// @file option_parsing.hpp
/// Strict parsing of numeric command-line options shared by the subcommands: the error is printed
/// (naming the option and the text) and the exit code returned.
#pragma once

#include <charconv>
#include <filesystem>
#include <iostream>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "exit_codes.hpp"
#include "inertial/formats/number_parsing.hpp"
#include "inertial/formats/output_paths.hpp"

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

// The error for an option taking `expected` numbers (numeric_options.hpp) given another count: the
// option, the count expected, the count found and the text given, e.g.
//   --pi: 3 numbers given, 10 expected ('1 0 0')
inline std::string NumberCountError(const std::string& option, std::size_t expected, std::size_t given,
                                    const std::string& text) {
  return option + ": " + std::to_string(given) + " numbers given, " + std::to_string(expected) + " expected ('" + text +
         "')";
}

// An output must not name an input, nor another output (formats/output_paths.hpp): kUsage with
// the error printed, else kOk. Empty paths are not given and are skipped.
inline int RefuseOverwritingInputs(const std::vector<PathOption>& outputs, const std::vector<PathOption>& inputs) {
  if (const std::optional<std::string> clash = OutputPathClash(outputs, inputs)) {
    std::cerr << "Error: " << *clash << "\n";
    return kUsage;
  }
  return kOk;
}

// A report directory must not hold an input under a name the report writes (it would be replaced):
// kUsage with the error printed, else kOk.
inline int RefuseReportOverInputs(const std::string& report_dir, const std::vector<std::string>& report_files,
                                  const std::vector<PathOption>& inputs) {
  if (report_dir.empty()) return kOk;
  for (const std::string& name : report_files) {
    const std::string written = (std::filesystem::path(report_dir) / name).string();
    for (const auto& [option, in] : inputs) {
      if (!in.empty() && SameFile(written, in)) {
        std::cerr << "Error: --report " << report_dir << " would write " << name << ", which is the " << option
                  << " input '" << in << "': refusing to overwrite an input (choose another report directory)\n";
        return kUsage;
      }
    }
  }
  return kOk;
}

}  // namespace inertial::cli
