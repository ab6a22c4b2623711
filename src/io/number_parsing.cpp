#include "inertial/io/number_parsing.hpp"

#include <cerrno>
#include <charconv>
#include <cmath>

namespace inertial {

double ParseDouble(std::string_view text, std::string_view what, bool allow_non_finite) {
  const std::string quoted = std::string(what) + ": '" + std::string(text) + "'";
  if (text.empty()) throw InvalidNumber(std::string(what) + ": empty value where a number is required");
  const char* first = text.data();
  const char* last = text.data() + text.size();
  if (*first == '+') ++first;  // from_chars does not accept a leading '+'
  double value = 0.0;
  const std::from_chars_result r = std::from_chars(first, last, value);
  if (r.ec == std::errc::result_out_of_range) throw InvalidNumber(quoted + " is out of the range of a double");
  if (r.ec != std::errc() || r.ptr != last || first == last) throw InvalidNumber(quoted + " is not a number");
  if (!allow_non_finite && !std::isfinite(value)) throw InvalidNumber(quoted + " is not finite");
  return value;
}

std::vector<double> ParseNumberList(std::string_view text, std::string_view what) {
  std::vector<double> values;
  std::size_t i = 0;
  auto is_separator = [](char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == ','; };
  while (i < text.size()) {
    while (i < text.size() && is_separator(text[i])) ++i;
    std::size_t j = i;
    while (j < text.size() && !is_separator(text[j])) ++j;
    if (j > i) {
      values.push_back(
          ParseDouble(text.substr(i, j - i), std::string(what) + ", value " + std::to_string(values.size() + 1)));
    }
    i = j;
  }
  return values;
}

}  // namespace inertial
