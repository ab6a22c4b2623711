/// @file number_text.hpp
/// Numbers as text, written one way everywhere: messages, reports, and files that must read back.
///
/// - FormatNumber(x, n): n significant digits, printf's %.ng ("0.1235", "1.235e+06", "inf",
///   "nan"): messages and reports (n = 3 or 4 mostly, 6 for times and rates), and %.17g (n = 17),
///   which reads back as the same double, where a file keeps that spelling (URDF, CSV columns).
/// - FormatNumberExact(x): the shortest text that reads back (strtod) as the same double, sign of
///   zero included ("0.1", "-0", "1e+300", "5e-324"): never longer than %.17g.
/// - FormatFixed(x, n): n digits after the point, printf's %.nf (percentages).
/// Locale-independent for the "C" locale the programs run in (the point is '.').
#pragma once

#include <string>

namespace inertial {

/// Significant digits that always read back as the same double: FormatNumber(x, kRoundTripDigits)
/// is %.17g.
inline constexpr int kRoundTripDigits = 17;

/// printf("%.*g", significant_digits, value). significant_digits from 1 to 17 (else
/// std::invalid_argument).
std::string FormatNumber(double value, int significant_digits = 4);

/// The shortest text that strtod reads back as exactly `value` (std::to_chars): "inf", "-inf",
/// "nan" ("-nan" for a NaN with its sign bit set) for the non-finite values.
std::string FormatNumberExact(double value);

/// printf("%.*f", decimals, value). decimals from 0 to 17 (else std::invalid_argument).
std::string FormatFixed(double value, int decimals);

}  // namespace inertial
