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

struct IdentifyCommand {
  std::string model, validate, effects, predictions, write_urdf, time_scale;
  std::vector<std::string> data, run_payloads;  ///< --data (one or more runs), --run-payload
  std::vector<std::string> regions;             ///< --region (user_region.hpp)
  std::string total_mass;                       ///< --total-mass (empty: none)
  std::string outlier_threshold = "0";
  bool no_outlier_rejection = false;
  std::string prior_weight = "0.01";
  std::string max_iterations = "1000";
  std::string gravity = "0 0 -9.81";
  std::string sg_order = "4";
  std::string sg_window = "0.1";
  bool skip_bad_rows = false;
  bool json = false;
};
CLI::App* AddIdentifyCommand(CLI::App& app, IdentifyCommand* command);
int RunIdentifyCommand(const IdentifyCommand& command);

struct CheckCommand {
  std::string model, repair;
  std::string total_mass;  ///< --total-mass (empty: none): the links' total judged against it
  bool json = false;
};
CLI::App* AddCheckCommand(CLI::App& app, CheckCommand* command);
int RunCheckCommand(const CheckCommand& command);

struct SimulateCommand {
  std::string model, out, effects, truth, truth_urdf;
  std::string effect_values = "0.1";
  std::string perturb = "0", duration = "20", rate = "500", harmonics = "5", base_frequency = "0.1";
  std::string amplitude = "0.9", noise_q = "0", noise_qd = "0", noise_tau = "0", seed = "1", truth_seed = "1";
  bool positions_only = false;
  std::string start_time = "0";
  std::string write_log;      ///< also write the samples as an LCM log of inertial.joint_state_t
  std::string log_channel = "INERTIAL_JOINT_STATE";
  std::string write_candump, can_config;  ///< also write motor frames as a candump log
  bool ignore_limits = false;             ///< excite about 0 with the full amplitude, limits unchecked
};
CLI::App* AddSimulateCommand(CLI::App& app, SimulateCommand* command);
int RunSimulateCommand(const SimulateCommand& command);

struct DiagnoseCommand {
  std::string model, validate, effects, report_dir, prior, time_scale;
  std::vector<std::string> data, run_payloads;  ///< --data (robots: one or more runs), --run-payload
  std::string holdout;  ///< empty: 0.3 unless --validate
  bool body = false;
  bool hold_links = false;
  bool json = false;
  std::string min_explained = "0.02";
  std::string max_iterations = "1000";
  // Robot-only options: empty means the default (and lets --body refuse them when given).
  std::string prior_weight, gravity, sg_order, sg_window, threads, iterate;
  std::string prior_tolerance;  ///< robots: empty for the default (plausibility.hpp)
  std::string folds;            ///< --body: cross-validation blocks (empty: 5 unless --validate/--holdout)
  bool skip_bad_rows = false;
  std::vector<std::string> regions;  ///< robots: --region (user_region.hpp)
  std::string total_mass;            ///< robots: --total-mass (empty: none)
};
CLI::App* AddDiagnoseCommand(CLI::App& app, DiagnoseCommand* command);
int RunDiagnoseCommand(const DiagnoseCommand& command);

struct ReplayCommand {
  std::string model, log, candump, can_config, effects, config, channel, out, write_log, write_urdf, time_scale;
  std::vector<std::string> regions;  ///< --region (user_region.hpp)
  std::string estimator, noise_tau, publish_rate;  ///< empty: --config's, or the defaults
  bool realtime = false, diagnose = false, json = false;
};
CLI::App* AddReplayCommand(CLI::App& app, ReplayCommand* command);
int RunReplayCommand(const ReplayCommand& command);

struct ExportCommand {
  std::string model, effects, checkpoint, write_urdf;
};
CLI::App* AddExportCommand(CLI::App& app, ExportCommand* command);
int RunExportCommand(const ExportCommand& command);

struct ValidateCommand {
  std::string model, effects, effect_values, predictions, report_dir, pi, time_scale;
  std::vector<std::string> data, run_payloads;  ///< --data (robots: one or more runs), --run-payload
  std::string gravity = "0 0 -9.81", sg_order = "4", sg_window = "0.1";
  std::string total_mass;  ///< robots: --total-mass (empty: none): the links' total judged against it
  bool body = false, json = false, skip_bad_rows = false;
};
CLI::App* AddValidateCommand(CLI::App& app, ValidateCommand* command);
int RunValidateCommand(const ValidateCommand& command);

struct PayloadCommand {
  std::string model, data, baseline, link, time_scale;
  std::vector<std::string> regions;  ///< --region (user_region.hpp), e.g. payload@tool0=...
  std::string prior_weight = "0.01";
  std::string max_mismatch_torque = "0.1";
  std::string max_mismatch;         ///< replaced by max_mismatch_torque: refused, saying so
  std::string gravity = "0 0 -9.81";
  bool json = false;
};
CLI::App* AddPayloadCommand(CLI::App& app, PayloadCommand* command);
int RunPayloadCommand(const PayloadCommand& command);

}  // namespace inertial::cli
