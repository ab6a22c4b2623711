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
/// The same for runs laid end to end (signal/recorded_runs.hpp): sample N is in run k where
/// starts[k] <= N < starts[k + 1], read from files[k] at line lines[N].
void NameSamplesByLine(const std::vector<std::string>& files, const std::vector<int>& starts, const std::vector<int>& lines,
                       std::vector<std::string>* messages);

}  // namespace inertial
