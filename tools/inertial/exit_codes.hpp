/// @file exit_codes.hpp
/// Exit codes of the `inertial` CLI (documented in the README and in --help).
#pragma once

#include "inertial/formats/joint_csv.hpp"

namespace inertial::cli {

inline constexpr int kOk = 0;
inline constexpr int kInternalError = 1;    ///< an unexpected failure (a bug: please report)
inline constexpr int kUsage = 2;            ///< unknown option, missing argument, wrong number of values
inline constexpr int kInvalidValue = 3;     ///< a value that is not a number, or not finite
inline constexpr int kInconsistentBody = 4; ///< a body that must be physically consistent is not
inline constexpr int kIoError = 5;          ///< a file could not be read or written, gnuplot failed
inline constexpr int kNoData = 6;           ///< the data gave nothing to work on (no message on the channel, every sample refused)

/// A CSV that breaks its contract is a file error (5); one whose cell is not a finite number, as
/// any such value, 3.
inline int ExitCodeOf(const CsvError& e) { return e.invalid_value ? kInvalidValue : kIoError; }

}  // namespace inertial::cli
