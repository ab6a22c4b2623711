// `inertial diagnose`: compare the model with held-out measurements, show where it fails, and rank
// the physical effects it lacks (joint_diagnosis.hpp, body_diagnosis.hpp).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>

#include "commands.hpp"
#include "exit_codes.hpp"
#include "progress.hpp"
#include "inertial/inertia/consistency.hpp"
#include "inertial/formats/body_csv.hpp"
#include "inertial/report/diagnosis_html.hpp"
#include "inertial/report/diagnosis_report.hpp"
#include "inertial/report/plausibility_report.hpp"
#include "inertial/report/validation_report.hpp"
#include "inertial/estimation/batch/robust_identification.hpp"
#include "inertial/signal/sample_glitches.hpp"
#include "option_parsing.hpp"
#include "robot_inputs.hpp"

namespace inertial::cli {

CLI::App* AddDiagnoseCommand(CLI::App& app, DiagnoseCommand* c) {
  CLI::App* sub = app.add_subcommand(
      "diagnose",
      "Fit the model as `identify` does, compare it with held-out data (--validate, the last --holdout fraction "
      "of --data, or for --body K-fold cross-validation), show where it fails and how far each identified link "
      "departs from its URDF, and rank the candidate effects it lacks (viscous, coulomb with a fitted velocity "
      "scale, asymmetric and sigmoid friction where the residual shows them, offset, armature, "
      "spring per joint; a payload on each link the fit bends, or with --hold-links on every link; for --body data "
      "force_bias, moment_bias, velocity_bias, gravity) by the held-out error each removes, its significance, and "
      "the plausibility it gives back to the links. Add the top one with --effects and run again (--iterate does).");
  sub->add_option("--model", c->model, "URDF robot description (robot data)");
  sub->add_flag("--body", c->body,
                "single-body data: CSV columns t, wx wy wz vx vy vz, mx my mz fx fy fz, optional gx gy gz");
  sub->add_option("--data", c->data,
                  "the log (CSV): training data; robots: more than once for several runs fitted as one model (each "
                  "differentiated on its own; without --validate the last --holdout of each is held out)")
      ->required();
  sub->add_option("--run-payload", c->run_payloads,
                  "robots: FILE=LINK[:mass=M[:com=X,Y,Z[:inertia=IXX,IYY,IZZ,IXY,IXZ,IYZ]]]: the run FILE carried this "
                  "payload; what is not given is fitted (identify --run-payload)");
  sub->add_option("--validate", c->validate, "held-out log (CSV)");
  sub->add_option("--holdout", c->holdout,
                  "without --validate: hold out this last fraction of --data (robots: default 0.3; --body: instead of "
                  "cross-validation)");
  sub->add_option("--folds", c->folds,
                  "--body without --validate or --holdout: judge by blocked K-fold cross-validation, 2 to 50 "
                  "(default 5; short logs such as the paper's 63 samples)");
  sub->add_option("--prior-tolerance", c->prior_tolerance,
                  "robots: a link is believable within a factor 1 + T of its URDF in mass, first moment about "
                  "its URDF COM (relative to its mass times its size) and inertia; links the fit bends beyond it "
                  "are tested for a payload and reported (default 0.75: a CAD model's ordinary error stays inside)");
  sub->add_option("--effects", c->effects,
                  "effects in the model (robots: syntax of identify --effects; --body: force_bias,moment_bias,"
                  "velocity_bias,gravity)");
  sub->add_flag("--hold-links", c->hold_links,
                "hold the links at their URDF inertias (rotors, payloads and effects still fitted) and test a payload "
                "on every link");
  sub->add_option("--region", c->regions, std::string("robots: ") + kRegionHelp);
  sub->add_option("--total-mass", c->total_mass, std::string("robots: ") + kTotalMassHelp);
  sub->add_option("--prior", c->prior, "--body: the prior body's pi (default 1 kg, 1 kg m^2: the paper's)");
  sub->add_option("--min-explained", c->min_explained,
                  "share of the held-out mean-square error a candidate must remove to be suggested, in (0, 1)")
      ->default_val("0.02");
  sub->add_option("--prior-weight", c->prior_weight, "robots: gamma of eq. 14, >= 0 (default 0.01)");
  sub->add_option("--max-iterations", c->max_iterations, "iteration cap of every fit, 1 to 100000")
      ->default_val("1000");
  sub->add_option("--gravity", c->gravity, "robots: gravity in the base frame [m/s^2] (default 0 0 -9.81)");
  sub->add_option("--sg-order", c->sg_order, "robots: Savitzky-Golay order for missing qd/qdd, 2 to 10 (default 4)");
  sub->add_option("--sg-window", c->sg_window, "robots: Savitzky-Golay window [s] (default 0.1)");
  sub->add_option("--iterate", c->iterate,
                  "robots: add the top suggestion and diagnose again, up to N times or until nothing is suggested");
  sub->add_option("--threads", c->threads, "robots: threads for the candidate fits (default 0: one per core)");
  sub->add_flag("--skip-bad-rows", c->skip_bad_rows, "skip (and count) malformed rows of robot logs");
  sub->add_option("--time-scale", c->time_scale,
                  "multiply the time stamps of --data and --validate by this to get seconds (1e-3 for ms, 1e-9 for ns)");
  sub->add_option("--report", c->report_dir, "write DIR/index.html (self-contained, with gnuplot figures)");
  sub->add_flag("--json", c->json, "print the result as JSON on stdout instead of the text report");
  return sub;
}

namespace {

int PrepareReportDirectory(const std::string& dir) {
  if (dir.empty()) return kOk;
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec || !std::filesystem::is_directory(dir)) {
    std::cerr << "Error: --report: cannot create directory '" << dir << "'" << (ec ? ": " + ec.message() : "") << "\n";
    return kIoError;
  }
  return kOk;
}

template <typename WriteFn>
int WriteReport(const std::string& dir, const WriteFn& write) {
  if (dir.empty()) return kOk;
  try {
    write();
  } catch (const std::exception& e) {
    std::cerr << "Error: --report: " << e.what() << "\n";
    return kIoError;
  }
  std::cerr << "report written to " << dir << "/index.html\n";
  return kOk;
}

// Samples with a value, or a URDF prediction, that is not finite or too large to square (a glitch
// such as tau = 1e300) would turn every statistic of the diagnosis into inf or NaN: left out, counted
// and the first named on stderr. kInvalidValue when none is left.
int LeaveOutUnusableRows(const RobotDynamics& links, const std::string& file, JointSamples* log) {
  const Eigen::MatrixXd predicted = PredictJointTorques(links, Eigen::VectorXd::Zero(links.num_parameters()), *log);
  const std::vector<int> bad = NonFiniteRows(predicted, *log);
  if (bad.empty()) return kOk;
  if (static_cast<int>(bad.size()) == log->size()) {
    std::cerr << "Error: " << file << ": every sample has a value or a URDF prediction that is not finite or too "
              << "large to square (check gravity, units and the data's magnitudes)\n";
    return kInvalidValue;
  }
  std::cerr << "note: " << file << ": " << bad.size() << " sample(s) left out, a value or the URDF's prediction not "
            << "finite or too large to square (first: sample " << bad[0] << ", t = " << log->t[bad[0]] << " s)\n";
  *log = SelectSamples(*log, RowsExcept(log->size(), bad));
  return kOk;
}

// Glitched samples of a single-body log (sample_glitches.hpp) are left out before the fit: a glitch
// in the twist is a regressor the fit bends to and whose residual then looks small. Named on stderr.
void LeaveOutGlitches(const std::string& file, BodyLog* log, std::vector<std::string>* left_out) {
  const GlitchScreen screen = FindGlitches(BodySignals(*log));
  if (screen.glitches.empty()) return;
  for (const SampleGlitch& g : screen.glitches) left_out->push_back(file + ": " + DescribeGlitch(*log, g));
  constexpr std::size_t kNamed = 3;
  std::cerr << "note: " << file << ": " << screen.glitches.size() << " glitched sample(s) left out, a value far from "
            << "its neighbours (more than " << std::lround(screen.threshold) << " robust scales):\n";
  for (std::size_t k = 0; k < std::min(kNamed, screen.glitches.size()); ++k) {
    std::cerr << "  " << DescribeGlitch(*log, screen.glitches[k]) << "\n";
  }
  if (screen.glitches.size() > kNamed) std::cerr << "  and " << screen.glitches.size() - kNamed << " more\n";
  *log = SelectBodySamples(*log, RowsExcept(static_cast<int>(log->samples.size()), screen.Rows()));
}

std::string HoldoutSource(const std::string& data, double fraction) {
  return "the last " + std::to_string(static_cast<int>(std::lround(100 * fraction))) + " % of " + data;
}

// The last `holdout` of a log (JointSamples or BodyLog) held out; kInvalidValue if it cannot be split.
template <typename Log>
int SplitOrFail(const std::string& data, double holdout, const Log& all, Log* train, Log* validation) {
  try {
    SplitHoldout(all, holdout, train, validation);
  } catch (const std::invalid_argument& e) {
    std::cerr << "Error: " << data << ": " << e.what() << "\n";
    return kInvalidValue;
  }
  return kOk;
}

// --prior: the pi of a fully consistent body (default 1 kg, 1 kg m^2: the paper's); kOk, or the
// exit code (the error printed).
int ReadBodyPrior(const std::string& text, InertialParams* prior) {
  Vector10 prior_pi;
  prior_pi << 1, 0, 0, 0, 1, 1, 1, 0, 0, 0;
  if (!text.empty()) {
    try {
      const std::vector<double> v = ParseNumberList(text, "--prior");
      if (v.size() != 10) {
        std::cerr << "Error: " << NumberCountError("--prior", 10, v.size(), text) << "\n";
        return kUsage;
      }
      prior_pi = Eigen::Map<const Vector10>(v.data());
    } catch (const InvalidNumber& e) {
      std::cerr << "Error: " << e.what() << "\n";
      return kInvalidValue;
    }
  }
  *prior = InertialParams::FromVector(prior_pi);
  const ConsistencyReport report = CheckConsistency(*prior);
  if (!report.fully_consistent()) {
    std::cerr << "Error: --prior: not physically consistent: " << report.reason << "\n";
    return kInconsistentBody;
  }
  return kOk;
}

// --data and --validate of single-body data, their glitches left out (named in *left_out); with
// --validate, *train is --data and *source names it. kOk, or the exit code (the error printed).
int ReadBodyLogs(const DiagnoseCommand& c, double time_scale, BodyLog* all, BodyLog* train, BodyLog* validation,
                 std::string* source, std::vector<std::string>* left_out) {
  try {
    std::vector<std::string> notices;
    *all = ReadBodyCsv(c.data[0], &notices, time_scale);
    if (!c.validate.empty()) {
      *validation = ReadBodyCsv(c.validate, &notices, time_scale);
      *source = c.validate;
    }
    for (const std::string& n : notices) std::cerr << "note: " << n << "\n";
  } catch (const CsvError& e) {
    std::cerr << "Error: " << e.what() << "\n";
    return ExitCodeOf(e);
  }
  LeaveOutGlitches(c.data[0], all, left_out);
  if (!c.validate.empty()) {
    *train = *all;
    LeaveOutGlitches(c.validate, validation, left_out);
  }
  return kOk;
}

int RunBody(const DiagnoseCommand& c, double holdout, double min_explained, int max_iterations, double time_scale,
            int folds) {
  std::vector<BodyEffectKind> effects;
  try {
    effects = ParseBodyEffectList(c.effects);
  } catch (const std::invalid_argument& e) {
    std::cerr << "Error: --effects: " << e.what() << "\n";
    return kUsage;
  }
  BodyDiagnosisContext context;
  int status = ReadBodyPrior(c.prior, &context.prior);
  BodyLog all, train, validation;
  if (status == kOk) status = ReadBodyLogs(c, time_scale, &all, &train, &validation, &context.validation_source, &context.left_out);
  const bool cross_validate = c.validate.empty() && c.holdout.empty();
  if (status == kOk && c.validate.empty() && !cross_validate) {
    status = SplitOrFail(c.data[0], holdout, all, &train, &validation);
    context.validation_source = HoldoutSource(c.data[0], holdout);
  }
  if (status != kOk) return status;
  BodyDiagnosisOptions options;
  options.min_explained = min_explained;
  options.fit.max_iterations = max_iterations;
  options.folds = folds;
  BodyDiagnosis d;
  try {
    if (cross_validate) {
      d = DiagnoseBodyModelCrossValidated(context.prior, effects, all, options);
      validation = all;
      context.validation_source = std::to_string(folds) + "-fold blocked cross-validation of " + c.data[0];
    } else {
      d = DiagnoseBodyModel(context.prior, effects, train, validation, options);
    }
  } catch (const std::invalid_argument& e) {
    std::cerr << "Error: " << c.data[0] << ": " << e.what() << "\n";
    return kInvalidValue;
  }
  context.diagnosis = &d;
  context.validation = &validation;
  context.min_explained = min_explained;
  const std::string text = BodyDiagnosisText(context);
  if (c.json) {
    std::cout << BodyDiagnosisJson(context).dump(2) << "\n";
  } else {
    std::cout << text;
  }
  return WriteReport(c.report_dir, [&] { WriteBodyDiagnosisReport(c.report_dir, context, text); });
}

// The robot options (the defaults where not given); kOk, or the exit code (the error printed).
int ParseRobotOptions(const DiagnoseCommand& c, JointDiagnosisOptions* options, JointCsvOptions* csv, int* iterate,
                      Vector3* gravity) {
  auto or_default = [](const std::string& text, const char* fallback) { return text.empty() ? std::string(fallback) : text; };
  int status = ParseRealOption(or_default(c.prior_weight, "0.01"), "--prior-weight", 0.0, 1e12, &options->fit.prior_weight);
  if (status == kOk) status = ParseInteger(or_default(c.sg_order, "4"), "--sg-order", 2, 10, &csv->differentiation.order);
  if (status == kOk) {
    status = ParseRealOption(or_default(c.sg_window, "0.1"), "--sg-window", 1e-6, 1e6, &csv->differentiation.window);
  }
  if (status == kOk) status = ParseInteger(or_default(c.threads, "0"), "--threads", 0, 256, &options->threads);
  if (status == kOk && !c.prior_tolerance.empty()) {
    status = ParseRealOption(c.prior_tolerance, "--prior-tolerance", 1e-6, 1e6, &options->prior_tolerance);
  }
  if (status == kOk) status = ParseInteger(or_default(c.iterate, "0"), "--iterate", 0, 1000, iterate);
  if (status == kOk) status = ParseGravityOption(or_default(c.gravity, "0 0 -9.81"), gravity);
  return status;
}

// The robot's training and held-out logs (--validate, or the last `holdout` of --data), rows no
// statistic can use left out; *source names the held-out data. kOk, or the exit code (printed).
int ReadRobotLogs(const DiagnoseCommand& c, const RobotModel& robot, const Vector3& gravity, const JointCsvOptions& csv,
                  double holdout, const RobotDynamics& links, const RunPayloadFit& payload_fit, JointSamples* train,
                  JointSamples* validation, std::string* source, RecordedRuns* held_runs) {
  std::vector<RunPayload> payloads;
  int status = ParseRunPayloads(c.run_payloads, c.data, &payloads);
  RecordedRuns all;
  LogGains log_gains;  // a model file's stated gains: the log in N m first
  log_gains.known_gains = StatedLogGains(robot, robot.effects);
  if (status == kOk) status = ReadRobotRuns(c.data, &payloads, robot, gravity, csv, &all, nullptr, log_gains, &payload_fit);
  const std::string data = RunsName(c.data);
  if (status == kOk && !c.validate.empty()) {
    status = ReadRobotLog(c.validate, robot, csv, validation);
    *train = std::move(all.samples);
    *source = c.validate;
  }
  if (status != kOk) return status;
  if (c.validate.empty()) {  // the last share of each run held out
    RecordedRuns train_runs;
    try {
      SplitRunsHoldout(all, holdout, &train_runs, held_runs);
    } catch (const std::invalid_argument& e) {
      std::cerr << "Error: " << e.what() << "\n";
      return kInvalidValue;
    }
    *train = std::move(train_runs.samples);
    *validation = held_runs->samples;
    *source = c.data.size() > 1 ? "the last " + std::to_string(static_cast<int>(std::lround(100 * holdout))) +
                                      " % of each of " + data
                                : HoldoutSource(data, holdout);
  }
  status = LeaveOutUnusableRows(links, data, train);
  if (status == kOk) status = LeaveOutUnusableRows(links, c.validate.empty() ? data : c.validate, validation);
  return status;
}

int RunRobot(const DiagnoseCommand& c, double holdout, double min_explained, int max_iterations, double time_scale) {
  JointDiagnosisOptions options;
  options.min_explained = min_explained;
  options.hold_links = c.hold_links;
  options.fit.lm.max_iterations = max_iterations;
  JointCsvOptions csv;
  csv.skip_bad_rows = c.skip_bad_rows;
  csv.time_scale = time_scale;
  int iterate = 0;
  Vector3 gravity;
  int status = ParseRobotOptions(c, &options, &csv, &iterate, &gravity);
  RobotModel robot;
  std::vector<EffectSpec> effects;
  std::optional<RobotDynamics> model;
  if (status == kOk) status = LoadRobot(c.model, c.effects, gravity, &robot, &effects, &model);
  if (status != kOk) return status;
  for (const EffectSpec& e : ParseEffectList(c.effects)) {
    if (e.kind != EffectKind::kGain) continue;
    std::cerr << "Error: --effects " << e.text << ": diagnose takes the log in N m; fit the gains first (identify "
              << "--effects gain ... --write-urdf model.urdf), and diagnose --model model.urdf reads the log with them\n";
    return kUsage;
  }
  // --region: checked on the model as given (every link and payload named must be there), then
  // applied to every model the diagnosis fits (a candidate payload's where the model has it).
  std::vector<UserRegion> regions;
  status = ParseRegionOptions(c.regions, &regions);
  if (status == kOk) status = ApplyRegionOptions(robot, regions, &*model);
  if (status == kOk) status = ParseTotalMassOption(c.total_mass, robot, *model, c.hold_links, &options.fit.total_mass);
  if (status != kOk) return status;
  const RobotModelFactory make = [&](const std::vector<EffectSpec>& e) {
    RobotDynamics m = MakeRobotDynamics(robot, e, gravity);
    ApplyUserRegions(robot, regions, &m, false);
    return m;
  };
  JointSamples train, validation;
  std::string source;
  RecordedRuns held_runs;
  RunPayloadFit payload_fit;  // payloads without a COM: fitted on the training share of their runs
  payload_fit.effects = effects;
  payload_fit.options = options.fit;
  payload_fit.hold_links = c.hold_links;
  payload_fit.regions = regions;
  payload_fit.holdout = c.validate.empty() ? holdout : 0.0;
  status = ReadRobotLogs(c, robot, gravity, csv, holdout, make({}), payload_fit, &train, &validation, &source,
                         &held_runs);
  if (status != kOk) return status;
  std::vector<DiagnosisStep> path;
  JointDiagnosis d;
  try {
    Progress progress("diagnose");
    options.progress = [&](int step, int cap) {
      progress.Show("step " + std::to_string(step) + " of at most " + std::to_string(cap));
    };
    d = iterate > 0 ? IterateJointDiagnosis(make, effects, robot.body_links, train, validation, options, iterate, &path)
                    : DiagnoseJointModel(make, effects, robot.body_links, train, validation, options);
    progress.Done();
  } catch (const std::invalid_argument& e) {
    std::cerr << "Error: " << RunsName(c.data) << ": " << e.what() << "\n";
    return kInvalidValue;
  }
  if (!path.empty()) model.emplace(make(d.effects));  // the final model, with every added effect
  JointDiagnosisContext context = MakeJointDiagnosisContext(*model, d, source, min_explained);
  if (held_runs.num_runs() > 1) {  // the held-out errors run by run (the pooled ones are the diagnosis's)
    context.run_names = held_runs.names;
    context.runs = CompareJointModelByRun(*model, d.fit.x, held_runs);
  }
  // The links' total against the robot as weighed (--total-mass), after the diagnosis's own text.
  std::optional<TotalMassPlausibility> total;
  if (options.fit.total_mass) total = JudgeTotalMass(*model, d.fit.x, *options.fit.total_mass);
  const std::string text = (iterate > 0 ? DiagnosisPathText(path, d) + "\n" : "") + JointDiagnosisText(context) +
                           (total ? TotalMassText(*total) + TotalMassWarning(*total) : "");
  if (c.json) {
    nlohmann::json j = JointDiagnosisJson(context);
    if (iterate > 0) j["path"] = DiagnosisPathJson(*model, path);
    if (total) j["total_mass"] = TotalMassJson(*total);
    std::cout << j.dump(2) << "\n";
  } else {
    std::cout << text;
  }
  return WriteReport(c.report_dir, [&] { WriteJointDiagnosisReport(c.report_dir, context, text); });
}

}  // namespace

int RunDiagnoseCommand(const DiagnoseCommand& c) {
  if (c.model.empty() == !c.body) {
    std::cerr << "Error: give --model URDF (robot data) or --body (single-body data), not " << (c.body ? "both" : "neither")
              << "\n";
    return kUsage;
  }
  if (!c.validate.empty() && !c.holdout.empty()) {
    std::cerr << "Error: --validate and --holdout exclude each other\n";
    return kUsage;
  }
  if (c.body) {
    const std::pair<bool, const char*> robot_only[] = {
        {c.hold_links, "--hold-links"},      {!c.iterate.empty(), "--iterate"},    {!c.gravity.empty(), "--gravity"},
        {!c.sg_order.empty(), "--sg-order"}, {!c.sg_window.empty(), "--sg-window"}, {!c.threads.empty(), "--threads"},
        {!c.prior_weight.empty(), "--prior-weight"}, {c.skip_bad_rows, "--skip-bad-rows"},
        {!c.prior_tolerance.empty(), "--prior-tolerance"}, {!c.regions.empty(), "--region"},
        {!c.total_mass.empty(), "--total-mass"}};
    for (const auto& [given, name] : robot_only) {
      if (given) {
        std::cerr << "Error: " << name << " needs --model (it does not apply to --body data)\n";
        return kUsage;
      }
    }
  }
  if (!c.body && !c.prior.empty()) {
    std::cerr << "Error: --prior is for --body data (robots take their priors from the URDF)\n";
    return kUsage;
  }
  if (!c.folds.empty() && (!c.body || !c.validate.empty() || !c.holdout.empty())) {
    std::cerr << "Error: --folds is for --body data judged by cross-validation (not with --validate or --holdout; "
                 "robots are judged on --validate or --holdout)\n";
    return kUsage;
  }
  double holdout = 0.3, min_explained = 0.0;
  int max_iterations = 0;
  int status = c.holdout.empty() ? kOk : ParseRealOption(c.holdout, "--holdout", 1e-6, 1.0 - 1e-6, &holdout);
  if (status == kOk) status = ParseRealOption(c.min_explained, "--min-explained", 1e-9, 1.0, &min_explained);
  if (status == kOk) status = ParseInteger(c.max_iterations, "--max-iterations", 1, 100000, &max_iterations);
  int folds = 5;
  if (status == kOk && !c.folds.empty()) status = ParseInteger(c.folds, "--folds", 2, 50, &folds);
  double time_scale = 0.0;
  if (status == kOk && !c.time_scale.empty()) {
    status = ParseRealOption(c.time_scale, "--time-scale", 1e-15, 1e6, &time_scale);
  }
  if (status == kOk && c.body && (c.data.size() > 1 || !c.run_payloads.empty())) {
    std::cerr << "Error: --body diagnoses one log: give --data once, without --run-payload\n";
    status = kUsage;
  }
  std::vector<PathOption> inputs{{"--validate", c.validate}, {"--model", c.model}};
  for (const std::string& d : c.data) inputs.push_back({"--data", d});
  if (status == kOk) status = RefuseReportOverInputs(c.report_dir, DiagnosisReportFileNames(), inputs);
  if (status == kOk) status = PrepareReportDirectory(c.report_dir);
  if (status != kOk) return status;
  return c.body ? RunBody(c, holdout, min_explained, max_iterations, time_scale, folds)
                : RunRobot(c, holdout, min_explained, max_iterations, time_scale);
}

}  // namespace inertial::cli
