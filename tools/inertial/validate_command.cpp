// `inertial validate`: a given model (a URDF with its effects, or one body) against a log, with no
// fit: errors per channel, where it fails, predictions and the report figures (validation_report.hpp).
#include <algorithm>
#include <filesystem>
#include <iostream>
#include <optional>

#include "commands.hpp"
#include "exit_codes.hpp"
#include "inertial/inertia/consistency.hpp"
#include "inertial/formats/body_csv.hpp"
#include "inertial/report/diagnosis_html.hpp"
#include "inertial/formats/model_file.hpp"
#include "inertial/formats/model_plausibility.hpp"
#include "inertial/report/plausibility_report.hpp"
#include "inertial/report/validation_report.hpp"
#include "option_parsing.hpp"
#include "robot_inputs.hpp"

namespace inertial::cli {

CLI::App* AddValidateCommand(CLI::App& app, ValidateCommand* c) {
  CLI::App* sub = app.add_subcommand(
      "validate",
      "Judge a model on a log without fitting it: RMS and relative RMS error per joint and in total, where it fails "
      "(the residual signatures of diagnose), predictions and report figures. The model is a URDF with every effect it "
      "states (<dynamics damping friction>, <inertial_effects>: what identify/replay/inertiald --write-urdf write), "
      "or one body (--body --pi). A robot's bodies are also judged for plausibility (against the priors a model file "
      "records, else against their collision shapes or their density), as identify judges its fit.");
  sub->add_option("--model", c->model, "URDF robot model (robot data)");
  sub->add_flag("--body", c->body, "single-body data (CSV of diagnose --body); the body is --pi");
  sub->add_option("--pi", c->pi, "--body: the body's pi [m hx hy hz Ixx Iyy Izz Ixy Iyz Ixz]");
  sub->add_option("--data", c->data,
                  "the log (CSV) to judge the model on; robots: more than once for several runs (each judged, and all "
                  "pooled)")
      ->required();
  sub->add_option("--run-payload", c->run_payloads,
                  "robots: FILE=LINK[:mass=M[:com=X,Y,Z[:inertia=IXX,IYY,IZZ,IXY,IXZ,IYZ]]]: the run FILE carried this "
                  "payload; what is not given is fitted (identify --run-payload)");
  sub->add_option("--effects", c->effects,
                  "effects to add to the model's own (robots: identify's syntax, e.g. viscous@knee,offset; --body: "
                  "force_bias,moment_bias,velocity_bias,gravity), with their values in --effect-values");
  sub->add_option("--effect-values", c->effect_values,
                  "the added effects' coefficients in order (robots: b, bc, c, Ia, or k q0 per joint term, a "
                  "target-less effect once per joint; --body: 3, 3, 6, 3 numbers)");
  sub->add_option("--gravity", c->gravity, "robots: gravity in the base frame [m/s^2]")->default_val("0 0 -9.81");
  sub->add_option("--sg-order", c->sg_order, "robots: Savitzky-Golay order for missing qd/qdd, 2 to 10")
      ->default_val("4");
  sub->add_option("--sg-window", c->sg_window, "robots: Savitzky-Golay window [s]")->default_val("0.1");
  sub->add_option("--time-scale", c->time_scale,
                  "multiply the time stamps by this to get seconds (1e-3 for ms, 1e-9 for ns)");
  sub->add_flag("--skip-bad-rows", c->skip_bad_rows, "skip (and count) malformed rows of robot logs");
  sub->add_option("--total-mass", c->total_mass,
                  "robots: the whole robot as weighed; the model's links plus the URDF masses of the links fixed "
                  "to the base are judged against it (a model heavier than the robot is not plausible)");
  sub->add_option("--predictions", c->predictions, "write t and the model's prediction of every channel (CSV)");
  sub->add_option("--report", c->report_dir, "write DIR/index.html (self-contained, with gnuplot figures)");
  sub->add_flag("--json", c->json, "print the result as JSON on stdout instead of the text report");
  return sub;
}

namespace {

// The added effects with their values, taken in order from the --effect-values list.
int AddedEffects(const std::string& effects_text, const std::string& values_text, const RobotModel& robot,
                 std::vector<ModelEffect>* added) {
  std::vector<EffectSpec> specs;
  std::vector<double> values;
  try {
    specs = ParseEffectList(effects_text);
    if (!values_text.empty()) values = ParseNumberList(values_text, "--effect-values");
  } catch (const InvalidNumber& e) {
    std::cerr << "Error: " << e.what() << "\n";
    return kInvalidValue;
  } catch (const std::invalid_argument& e) {
    std::cerr << "Error: --effects: " << e.what() << "\n";
    return kUsage;
  }
  std::size_t next = 0;
  for (const EffectSpec& spec : specs) {
    std::vector<std::string> targets;
    if (IsJointEffect(spec.kind) && spec.target.empty()) {
      targets = robot.dof_names;
    } else {
      targets = {spec.target};
    }
    for (const std::string& target : targets) {
      ModelEffect m;
      m.spec = spec;
      m.spec.target = target;
      for (int k = 0; k < NumEffectValues(spec.kind); ++k, ++next) {
        if (next < values.size()) m.values.push_back(values[next]);
      }
      added->push_back(m);
    }
  }
  if (next != values.size()) {
    std::cerr << "Error: --effect-values: " << values.size() << " numbers given, the added effects take " << next
              << " (" << (next == 0 ? "none" : "one per coefficient, in --effects order") << ")\n";
    return kUsage;
  }
  return kOk;
}

// What validate adds to the validation for a robot: its bodies' plausibility (and the links' total
// against --total-mass), as text after ValidationText's and as JSON fields.
struct PlausibilitySection {
  std::string text;
  nlohmann::json json = nlohmann::json::object();
};

int Finish(const ValidateCommand& c, ModelValidation& v, const PlausibilitySection& plausibility = {}) {
  const std::string text = ValidationText(v) + (plausibility.text.empty() ? "" : "\n" + plausibility.text);
  if (c.json) {
    nlohmann::json j = ValidationJson(v);
    j.update(plausibility.json);
    std::cout << j.dump(2) << "\n";
  } else {
    std::cout << text;
  }
  try {
    if (!c.predictions.empty()) {
      Eigen::MatrixXd columns(v.predicted.rows(), 1 + v.predicted.cols());
      columns << v.signals.t, v.predicted;
      std::vector<std::string> header{"t"};
      for (const std::string& ch : v.channels) header.push_back((c.body ? "" : "tau_hat_") + ch);
      WriteColumnsCsv(c.predictions, header, columns);
    }
  } catch (const CsvError& e) {
    std::cerr << "Error: " << e.what() << "\n";
    return ExitCodeOf(e);
  }
  if (!c.report_dir.empty()) {
    try {
      std::filesystem::create_directories(c.report_dir);
      WriteValidationReport(c.report_dir, v, text);
    } catch (const std::exception& e) {
      std::cerr << "Error: --report: " << e.what() << "\n";
      return kIoError;
    }
    std::cerr << "report written to " << c.report_dir << "/index.html\n";
  }
  return v.physically_consistent ? kOk : kInconsistentBody;
}

// The bodies judged (formats/model_plausibility.hpp) and, with --total-mass, the links' total.
PlausibilitySection Plausibility(const RobotModel& robot, const RobotDynamics& model, const Eigen::VectorXd& x,
                                 const std::optional<double>& total_mass) {
  const std::vector<JudgedBody> judged = JudgeModelBodies(robot, model, x);
  PlausibilitySection s;
  s.text = ModelPlausibilityText(judged);
  const nlohmann::json bodies = ModelPlausibilityJson(judged);
  s.json["plausibility"] = bodies["bodies"];
  bool plausible = bodies["plausible"].get<bool>();
  if (total_mass) {
    const TotalMassPlausibility t = JudgeTotalMass(model, x, TotalMassBound{*total_mass, MassFixedToBase(robot)});
    s.text += TotalMassText(t) + TotalMassWarning(t);
    s.json["total_mass"] = TotalMassJson(t);
    plausible = plausible && t.within;
  }
  s.json["plausible"] = plausible;
  return s;
}

int RunRobot(const ValidateCommand& c, const JointCsvOptions& csv) {
  Vector3 gravity;
  int status = ParseGravityOption(c.gravity, &gravity);
  std::optional<double> total_mass;
  if (status == kOk && !c.total_mass.empty()) {
    total_mass.emplace();
    status = ParseRealOption(c.total_mass, "--total-mass", 1e-9, 1e6, &*total_mass);
  }
  if (status != kOk) return status;
  RobotModel robot;
  status = LoadRobotModel(c.model, &robot);
  if (status != kOk) return status;
  std::vector<ModelEffect> effects = robot.effects;
  std::vector<ModelEffect> added;
  status = AddedEffects(c.effects, c.effect_values, robot, &added);
  if (status != kOk) return status;
  for (std::size_t i = 0; i < added.size(); ++i) {
    for (std::size_t k = 0; k < i; ++k) {
      if (added[k].spec.kind == added[i].spec.kind && added[k].spec.target == added[i].spec.target) {
        std::cerr << "Error: --effects: " << ToString(added[i].spec.kind) << "@" << added[i].spec.target
                  << " is given twice\n";
        return kUsage;
      }
    }
  }
  // An added effect replaces the file's of the same kind on the same target.
  effects.erase(std::remove_if(effects.begin(), effects.end(),
                               [&](const ModelEffect& f) {
                                 return std::any_of(added.begin(), added.end(), [&](const ModelEffect& a) {
                                   return f.spec.kind == a.spec.kind && f.spec.target == a.spec.target;
                                 });
                               }),
                effects.end());
  effects.insert(effects.end(), added.begin(), added.end());
  std::vector<EffectSpec> specs;
  for (const ModelEffect& m : effects) specs.push_back(m.spec);
  std::optional<RobotDynamics> model;
  Eigen::VectorXd x;
  try {
    model.emplace(MakeRobotDynamics(robot, specs, gravity));
    x = model->ParametersFromEffectValues(effects);
  } catch (const std::invalid_argument& e) {
    std::cerr << "Error: " << c.model << (c.effects.empty() ? "" : " with --effects " + c.effects) << ": " << e.what() << "\n";
    return kUsage;
  }
  std::vector<RunPayload> payloads;
  status = ParseRunPayloads(c.run_payloads, c.data, &payloads);
  RecordedRuns runs;
  LogGains log_gains;  // torque columns the model file says are logged with a gain: in N m first
  log_gains.known_gains = StatedLogGains(robot, effects);
  RunPayloadFit payload_fit;  // payloads without a COM: fitted to the runs with the model as it is
  payload_fit.effects = specs;
  payload_fit.stated_effects = effects;
  if (status == kOk) status = ReadRobotRuns(c.data, &payloads, robot, gravity, csv, &runs, nullptr, log_gains, &payload_fit);
  if (status != kOk) return status;
  ModelValidation v;
  try {
    v = ValidateJointModel(*model, x, runs.samples);
    if (runs.num_runs() > 1) {
      v.run_names = runs.names;
      v.runs = CompareJointModelByRun(*model, x, runs);
    }
  } catch (const std::invalid_argument& e) {
    std::cerr << "Error: " << c.model << " on " << RunsName(c.data) << ": " << e.what() << "\n";
    return kInvalidValue;
  }
  v.model_source = c.model;
  for (const ModelEffect& m : effects) {
    v.model_source += (&m == &effects.front() ? " with " : ", ") + std::string(ToString(m.spec.kind)) + "@" + m.spec.target;
  }
  v.data_source = RunsName(c.data);
  return Finish(c, v, Plausibility(robot, *model, x, total_mass));
}

int RunBody(const ValidateCommand& c, double time_scale) {
  std::vector<BodyEffectKind> kinds;
  std::vector<double> pi_values, effect_values;
  try {
    kinds = ParseBodyEffectList(c.effects);
    pi_values = ParseNumberList(c.pi, "--pi");
    if (!c.effect_values.empty()) effect_values = ParseNumberList(c.effect_values, "--effect-values");
  } catch (const InvalidNumber& e) {
    std::cerr << "Error: " << e.what() << "\n";
    return kInvalidValue;
  } catch (const std::invalid_argument& e) {
    std::cerr << "Error: --effects: " << e.what() << "\n";
    return kUsage;
  }
  if (pi_values.size() != 10) {
    std::cerr << "Error: " << NumberCountError("--pi", 10, pi_values.size(), c.pi) << "\n";
    return kUsage;
  }
  const InertialParams body = InertialParams::FromVector(Eigen::Map<const Vector10>(pi_values.data()));
  const ConsistencyReport report = CheckConsistency(body);
  if (!report.fully_consistent()) {
    std::cerr << "Error: --pi: not physically consistent: " << report.reason << "\n";
    return kInconsistentBody;
  }
  const BodyEffectModel model(body, kinds);
  if (static_cast<int>(effect_values.size()) != model.num_parameters() - 10) {
    std::cerr << "Error: --effect-values: " << effect_values.size() << " numbers given, the effects take "
              << model.num_parameters() - 10 << "\n";
    return kUsage;
  }
  Eigen::VectorXd x = Eigen::VectorXd::Zero(model.num_parameters());
  for (std::size_t k = 0; k < effect_values.size(); ++k) x[10 + static_cast<int>(k)] = effect_values[k];
  BodyLog log;
  try {
    std::vector<std::string> notices;
    log = ReadBodyCsv(c.data[0], &notices, time_scale);
    for (const std::string& n : notices) std::cerr << "note: " << n << "\n";
  } catch (const CsvError& e) {
    std::cerr << "Error: " << e.what() << "\n";
    return ExitCodeOf(e);
  }
  ModelValidation v;
  try {
    v = ValidateBodyModel(model, x, log);
  } catch (const std::invalid_argument& e) {
    std::cerr << "Error: --pi on " << c.data[0] << ": " << e.what() << "\n";
    return kInvalidValue;
  }
  v.model_source = "the body --pi";
  for (BodyEffectKind k : kinds) v.model_source += " + " + std::string(ToString(k));
  v.data_source = c.data[0];
  return Finish(c, v);
}

}  // namespace

int RunValidateCommand(const ValidateCommand& c) {
  if (c.model.empty() == !c.body) {
    std::cerr << "Error: give --model URDF (robot data) or --body with --pi (single-body data), not "
              << (c.body ? "both" : "neither") << "\n";
    return kUsage;
  }
  if (c.body && c.pi.empty()) {
    std::cerr << "Error: --body needs --pi (the body's 10 inertial parameters)\n";
    return kUsage;
  }
  if (c.body && !c.total_mass.empty()) {
    std::cerr << "Error: --total-mass is for a robot (--model): a single body has no links to weigh\n";
    return kUsage;
  }
  if (!c.body && !c.pi.empty()) {
    std::cerr << "Error: --pi is for --body data (a robot's bodies are in its URDF)\n";
    return kUsage;
  }
  if (c.body && (c.data.size() > 1 || !c.run_payloads.empty())) {
    std::cerr << "Error: --body judges one log: give --data once, without --run-payload\n";
    return kUsage;
  }
  std::vector<PathOption> inputs{{"--model", c.model}};
  for (const std::string& d : c.data) inputs.push_back({"--data", d});
  int status = RefuseOverwritingInputs({{"--predictions", c.predictions}, {"--report", c.report_dir}}, inputs);
  if (status == kOk) status = RefuseReportOverInputs(c.report_dir, DiagnosisReportFileNames(), inputs);
  if (status != kOk) return status;
  JointCsvOptions csv;
  csv.skip_bad_rows = c.skip_bad_rows;
  status = ParseInteger(c.sg_order, "--sg-order", 2, 10, &csv.differentiation.order);
  if (status == kOk) status = ParseRealOption(c.sg_window, "--sg-window", 1e-6, 1e6, &csv.differentiation.window);
  if (status == kOk && !c.time_scale.empty()) {
    status = ParseRealOption(c.time_scale, "--time-scale", 1e-15, 1e6, &csv.time_scale);
  }
  if (status != kOk) return status;
  return c.body ? RunBody(c, csv.time_scale) : RunRobot(c, csv);
}

}  // namespace inertial::cli
