// inertial: the command-line tool. Thin: argument parsing (CLI11), wiring, exit codes.
#include <exception>
#include <iostream>
#include <optional>

#include "command_line.hpp"
#include "numeric_options.hpp"
#include "commands.hpp"
#include "exit_codes.hpp"

int main(int argc, char** argv) {
  using namespace inertial::cli;
  CLI::App app{
      "inertial: physically consistent rigid-body inertia (log-Cholesky parameterization, Rucker & Wensing 2022).\n"
      "Exit codes: 0 ok, 1 internal error, 2 usage, 3 invalid value, 4 inconsistent body, 5 I/O error, 6 no usable data."};
  app.name("inertial");
  app.set_version_flag("--version", "inertial " INERTIAL_VERSION);
  app.require_subcommand(1);
  StudyCommand study;
  ConvertCommand convert;
  CLI::App* study_app = AddStudyCommand(app, &study);
  CLI::App* convert_app = AddConvertCommand(app, &convert);
  IdentifyCommand identify;
  CLI::App* identify_app = AddIdentifyCommand(app, &identify);
  CheckCommand check;
  CLI::App* check_app = AddCheckCommand(app, &check);
  SimulateCommand simulate;
  CLI::App* simulate_app = AddSimulateCommand(app, &simulate);
  ReplayCommand replay;
  CLI::App* replay_app = AddReplayCommand(app, &replay);
  DiagnoseCommand diagnose;
  CLI::App* diagnose_app = AddDiagnoseCommand(app, &diagnose);
  ExportCommand export_command;
  CLI::App* export_app = AddExportCommand(app, &export_command);
  ValidateCommand validate;
  CLI::App* validate_app = AddValidateCommand(app, &validate);
  PayloadCommand payload;
  CLI::App* payload_app = AddPayloadCommand(app, &payload);
  DescribeNumericOptions(app);
  if (const std::optional<int> done = ParseCommandLine(app, argc, argv, kUsage)) return *done;
  try {
    if (study_app->parsed()) return RunStudyCommand(study);
    if (convert_app->parsed()) return RunConvertCommand(convert);
    if (identify_app->parsed()) return RunIdentifyCommand(identify);
    if (check_app->parsed()) return RunCheckCommand(check);
    if (simulate_app->parsed()) return RunSimulateCommand(simulate);
    if (diagnose_app->parsed()) return RunDiagnoseCommand(diagnose);
    if (replay_app->parsed()) return RunReplayCommand(replay);
    if (validate_app->parsed()) return RunValidateCommand(validate);
    if (export_app->parsed()) return RunExportCommand(export_command);
    if (payload_app->parsed()) return RunPayloadCommand(payload);
  } catch (const std::exception& e) {
    std::cerr << "Error: " << e.what() << "\n";
    return kInternalError;
  }
  return kUsage;
}
