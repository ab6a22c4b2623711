// `inertial study`: the paper's Section VI, reproduced.
#include <charconv>
#include <cstdint>
#include <filesystem>
#include <iostream>

#include "commands.hpp"
#include "exit_codes.hpp"
#include "option_parsing.hpp"
#include "inertial/report/study_report.hpp"

namespace inertial::cli {

CLI::App* AddStudyCommand(CLI::App& app, StudyCommand* c) {
  CLI::App* sub = app.add_subcommand(
      "study",
      "Reproduce the 1000-body comparison of Section VI (Table I bodies, eq. 13 residuals, linear least squares "
      "and Levenberg-Marquardt in the linear, eigenvalue, exponential and log-Cholesky parameterizations). "
      "Prints a table beside the paper's figures.");
  sub->add_option("--bodies", c->bodies, "number of random bodies, 1 to 1000000")->default_val("1000");
  sub->add_option("--seed", c->seed, "random seed, an integer 0 to 2^64-1 (each body's stream derives from it)")
      ->default_val("1");
  sub->add_option("--threads", c->threads, "worker threads, 0 to 256 (0: one per hardware thread)")->default_val("0");
  sub->add_option("--max-iterations", c->max_iterations, "iteration cap of every fit, 1 to 10000 (paper: 50)")
      ->default_val("50");
  sub->add_flag("--json", c->json, "print the results as JSON on stdout instead of the table");
  sub->add_option("--report", c->report_dir,
                  "also write DIR/table.txt, DIR/study.json, DIR/fig1.png (gnuplot; like the paper's Fig. 1)");
  return sub;
}


int RunStudyCommand(const StudyCommand& command) {
  StudyCommand c = command;
  int status = ParseInteger<std::uint64_t>(c.seed, "--seed", 0, UINT64_MAX, &c.options.seed);
  if (status == kOk) status = ParseInteger(c.bodies, "--bodies", 1, 1000000, &c.options.bodies);
  if (status == kOk) status = ParseInteger(c.threads, "--threads", 0, 256, &c.options.threads);
  if (status == kOk) {
    status = ParseInteger(c.max_iterations, "--max-iterations", 1, 10000, &c.options.solver.max_iterations);
  }
  if (status != kOk) return status;
  if (!c.report_dir.empty()) {  // fail before the work, not after it
    std::error_code ec;
    std::filesystem::create_directories(c.report_dir, ec);
    if (ec || !std::filesystem::is_directory(c.report_dir)) {
      std::cerr << "Error: --report: cannot create directory '" << c.report_dir << "'"
                << (ec ? ": " + ec.message() : std::string()) << "\n";
      return kIoError;
    }
  }
  const StudyResult result = RunStudy(c.options);
  if (c.json) {
    std::cout << StudyToJson(result).dump(2) << "\n";
  } else {
    std::cout << StudyTable(result);
  }
  if (!c.report_dir.empty()) {
    try {
      WriteStudyReport(result, c.report_dir);
    } catch (const std::runtime_error& e) {
      std::cerr << "Error: --report: " << e.what() << "\n";
      return kIoError;
    }
    std::cerr << "report written to " << c.report_dir << "/ (fig1.png, table.txt, study.json)\n";
  }
  return kOk;
}

}  // namespace inertial::cli
