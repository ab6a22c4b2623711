// `inertial study`: the paper's Section VI, reproduced.
#include <charconv>
#include <filesystem>
#include <iostream>

#include "commands.hpp"
#include "exit_codes.hpp"
#include "inertial/io/study_report.hpp"

namespace inertial::cli {

CLI::App* AddStudyCommand(CLI::App& app, StudyCommand* c) {
  CLI::App* sub = app.add_subcommand(
      "study",
      "Reproduce the 1000-body comparison of Section VI (Table I bodies, eq. 13 residuals, linear least squares "
      "and Levenberg-Marquardt in the linear, eigenvalue, exponential and log-Cholesky parameterizations). "
      "Prints a table beside the paper's figures.");
  sub->add_option("--bodies", c->options.bodies, "number of random bodies")->default_val(1000)->check(CLI::Range(1, 1000000));
  sub->add_option("--seed", c->seed, "random seed, an integer 0 to 2^64-1 (each body's stream derives from it)")
      ->default_val("1");
  sub->add_option("--threads", c->options.threads, "worker threads (0: one per hardware thread)")
      ->default_val(0)
      ->check(CLI::Range(0, 256));
  sub->add_option("--max-iterations", c->options.solver.max_iterations, "iteration cap of every fit (paper: 50)")
      ->default_val(50)
      ->check(CLI::Range(1, 10000));
  sub->add_flag("--json", c->json, "print the results as JSON on stdout instead of the table");
  sub->add_option("--report", c->report_dir,
                  "also write DIR/table.txt, DIR/study.json, DIR/fig1.png (gnuplot; like the paper's Fig. 1)");
  return sub;
}

int RunStudyCommand(const StudyCommand& command) {
  StudyCommand c = command;
  {
    const char* first = c.seed.data();
    const char* last = c.seed.data() + c.seed.size();
    const std::from_chars_result r = std::from_chars(first, last, c.options.seed);
    if (c.seed.empty() || r.ec != std::errc() || r.ptr != last) {
      std::cerr << "Error: --seed: '" << c.seed << "' is not an integer from 0 to 18446744073709551615\n";
      return kInvalidValue;
    }
  }
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
