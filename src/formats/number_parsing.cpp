#include "inertial/formats/number_parsing.hpp"

#include <cerrno>
#include <charconv>
#include <cmath>

namespace inertial {

double ParseDouble(std::string_view text, std::string_view what, bool allow_non_finite) {
  const std::string quoted = std::string(what) + ": '" + std::string(text) + "'";
  if (text.empty()) throw InvalidNumber(std::string(what) + ": empty value where a number is required");
  const char* first = text.data();
  const char* last = text.data() + text.size();
  if (*first == '+') {  // from_chars does not accept a leading '+'; a sign may not follow it
    ++first;
    if (first != last && (*first == '+' || *first == '-')) throw InvalidNumber(quoted + " is not a number");
  }
  double value = 0.0;
  const std::from_chars_result r = std::from_chars(first, last, value);
  if (r.ec == std::errc::result_out_of_range) throw InvalidNumber(quoted + " is out of the range of a double");
  if (r.ec != std::errc() || r.ptr != last || first == last) throw InvalidNumber(quoted + " is not a number");
  if (!allow_non_finite && !std::isfinite(value)) throw InvalidNumber(quoted + " is not finite");
  return value;
}

std::vector<double> ParseNumberList(std::string_view text, std::string_view what) {
  // Tokens are separated by whitespace and/or one comma; a leading comma or two commas with nothing
  // between them mean a missing value, which is an error rather than something to skip silently.
  std::vector<double> values;
  auto is_space = [](char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; };
  std::size_t i = 0;
  bool comma_pending = false;  // a comma seen since the last token
  while (i < text.size()) {
    if (is_space(text[i])) {
      ++i;
      continue;
    }
    if (text[i] == ',') {
      if (comma_pending || values.empty()) {
        throw InvalidNumber(std::string(what) + ", value " + std::to_string(values.size() + 1) +
                            ": empty value between commas");
      }
      comma_pending = true;
      ++i;
      continue;
    }
    std::size_t j = i;
    while (j < text.size() && !is_space(text[j]) && text[j] != ',') ++j;
    values.push_back(
        ParseDouble(text.substr(i, j - i), std::string(what) + ", value " + std::to_string(values.size() + 1)));
    comma_pending = false;
    i = j;
  }
  return values;  // one trailing comma (as a line "1, 2, 3," has) is accepted
}

}  // namespace inertial
