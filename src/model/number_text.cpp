#include "inertial/model/number_text.hpp"

#include <charconv>
#include <cstdio>
#include <stdexcept>

namespace inertial {

std::string FormatNumber(double value, int significant_digits) {
  if (significant_digits < 1 || significant_digits > 17) {
    throw std::invalid_argument("FormatNumber: significant digits must be from 1 to 17, got " +
                                std::to_string(significant_digits));
  }
  char text[48];  // "-d.dddddddddddddddde-308": 24 characters at 17 digits
  const int n = std::snprintf(text, sizeof text, "%.*g", significant_digits, value);
  return std::string(text, static_cast<std::size_t>(n));
}

std::string FormatNumberExact(double value) {
  char text[32];
  const std::to_chars_result r = std::to_chars(text, text + sizeof text, value);
  return std::string(text, r.ptr);
}

std::string FormatFixed(double value, int decimals) {
  if (decimals < 0 || decimals > 17) {
    throw std::invalid_argument("FormatFixed: decimals must be from 0 to 17, got " + std::to_string(decimals));
  }
  // %f of 1e308 has 309 digits before the point.
  const int size = std::snprintf(nullptr, 0, "%.*f", decimals, value);
  std::string text(static_cast<std::size_t>(size) + 1, '\0');
  std::snprintf(text.data(), text.size(), "%.*f", decimals, value);
  text.resize(static_cast<std::size_t>(size));
  return text;
}

}  // namespace inertial
