/// @file gnuplot.hpp
/// Running gnuplot (Debian's gnuplot-nox) on a script file, for the figures of --report.
#pragma once

#include <filesystem>
#include <string>

namespace inertial {

/// Runs `gnuplot SCRIPT` with `dir` as its working directory, without a shell (no quoting issues
/// with the directory name). @throws std::runtime_error naming the script, the directory and the
/// exit status (127: gnuplot not on PATH).
void RunGnuplot(const std::filesystem::path& dir, const std::string& script);

/// Text as a gnuplot single-quoted string literal (quotes doubled).
std::string GnuplotQuoted(const std::string& text);

}  // namespace inertial
