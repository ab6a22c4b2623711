/// @file output_paths.hpp
/// No output overwrites an input: the check every command and the daemon make on the files they
/// are asked to write, with one wording for every program.
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace inertial {

/// True if both paths are given (non-empty) and name the same file, also through another spelling
/// or a link: std::filesystem::equivalent for existing files, else the weakly canonical paths.
bool SameFile(const std::string& a, const std::string& b);

/// A path and the option that gave it, e.g. {"--model", "leg.urdf"}; an empty path was not given.
struct PathOption {
  std::string option;
  std::string path;
};

/// The first clash among the paths, as the error to print, or nothing: an output naming an input
/// ("--predictions 'x.csv' is the --data input: refusing to overwrite an input (choose another
/// output path)") or two outputs naming one file ("--out and --write-log name the same file
/// 'x'"). Outputs are checked in order, each against every input, then against the later outputs.
std::optional<std::string> OutputPathClash(const std::vector<PathOption>& outputs,
                                           const std::vector<PathOption>& inputs);

}  // namespace inertial
