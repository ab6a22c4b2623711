/// @file sample_line_names.hpp
/// Messages about "sample N" of a log named by the line of the file that sample was read from, so
/// that a person can find it: "run.csv:102: sample 100 ...".
#pragma once

#include <string>
#include <vector>

namespace inertial {

/// Prefixes "<file>:<line>: " to every message whose first "sample " is followed by N, a sample of
/// `lines` (lines[N]: the file line of sample N, as the CSV readers give them; text that is not a
/// number reads as 0); other messages are left as they are.
void NameSamplesByLine(const std::string& file, const std::vector<int>& lines, std::vector<std::string>* messages);

}  // namespace inertial
