/// @file commands.hpp
/// Subcommands of the `inertial` CLI. Each Add* registers its options on the app and returns the
/// subcommand; Run* executes it after parsing and returns an exit code (exit_codes.hpp).
#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "inertial/study/paper_study.hpp"

namespace inertial::cli {

struct StudyCommand {
  StudyOptions options;
  // Numbers are taken as text and parsed strictly in RunStudyCommand (CLI11 would wrap "-1" into a
  // huge unsigned seed silently, and calls "abc" out of range).
  std::string seed = "1";
  std::string bodies = "1000";
  std::string threads = "0";
  std::string max_iterations = "50";
  bool json = false;
  std::string report_dir;
};
CLI::App* AddStudyCommand(CLI::App& app, StudyCommand* command);
int RunStudyCommand(const StudyCommand& command);

struct ConvertCommand {
  std::string from, to;
  std::string reference;  ///< pi of the log-Cholesky reference body, 10 numbers
  bool json = false;
  bool allow_inconsistent = false;
  std::vector<std::string> values;
};
CLI::App* AddConvertCommand(CLI::App& app, ConvertCommand* command);
int RunConvertCommand(const ConvertCommand& command);

}  // namespace inertial::cli
