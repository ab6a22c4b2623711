// `inertial identify`: batch identification of a URDF robot from joint logs (eq. 14).
#include <algorithm>
#include <iostream>
#include <optional>

#include "commands.hpp"
#include "exit_codes.hpp"
#include "progress.hpp"
#include "inertial/report/identification_report.hpp"
#include "inertial/report/plausibility_report.hpp"
#include "inertial/formats/joint_csv.hpp"
#include "inertial/formats/model_file.hpp"
#include "inertial/formats/sample_line_names.hpp"
#include "inertial/formats/torque_predictions.hpp"
#include "inertial/report/fit_failure_text.hpp"
#include "inertial/report/uncertainty_report.hpp"
#include "inertial/report/run_errors_report.hpp"
#include "inertial/estimation/batch/gain_identification.hpp"
#include "inertial/model/number_text.hpp"
#include "option_parsing.hpp"
#include "robot_inputs.hpp"

namespace inertial::cli {

CLI::App* AddIdentifyCommand(CLI::App& app, IdentifyCommand* c) {
  CLI::App* sub = app.add_subcommand(
      "identify",
      "Identify a URDF robot's link inertias (and joint effects) from a joint log: Levenberg-Marquardt over "
      "log-Cholesky theta relative to the URDF prior with the log-det regularizer (Rucker & Wensing 2022, eq. 14). "
      "Every identified body is physically consistent. CSV contract: header; t [s] strictly increasing; for each "
      "moving joint J of the URDF q_J and tau_J, optionally qd_J and qdd_J (else Savitzky-Golay derivatives).");
  sub->add_option("--model", c->model, "URDF robot description")->required();
  sub->add_option("--data", c->data,
                  "training log (CSV); give it more than once for several runs of the robot, fitted as one model "
                  "(each run differentiated on its own)")
      ->required();
  sub->add_option("--run-payload", c->run_payloads,
                  "FILE=LINK[:mass=M[:com=X,Y,Z[:inertia=IXX,IYY,IZZ,IXY,IXZ,IYZ]]]: the run FILE (a --data file) was "
                  "recorded carrying a payload on LINK (COM and inertia about the COM in LINK's frame); what is not "
                  "given is fitted with the model from every run (the mass held where stated), and the payload's "
                  "torques are taken out of that run's");
  sub->add_option("--validate", c->validate, "validation log (CSV): errors of the prior and of the fit on it");
  sub->add_option("--effects", c->effects,
                  "effects beyond rigid links, e.g. viscous,coulomb@knee:scale=0.05,offset,armature,spring,"
                  "asymmetric@hip:scale=0.02,sigmoid@knee:steepness=40:shift=0.02,payload@tool0:mass=2,"
                  "rotor@hip:gear=6 (a joint effect without @ applies to every joint)");
  sub->add_option("--region", c->regions, kRegionHelp);
  sub->add_option("--total-mass", c->total_mass, kTotalMassHelp);
  sub->add_option("--prior-weight", c->prior_weight, "gamma of eq. 14, >= 0 (the paper: 1e-2)")->default_val("0.01");
  sub->add_option("--max-iterations", c->max_iterations, "Levenberg-Marquardt iteration cap, 1 to 100000")
      ->default_val("1000");
  sub->add_option("--gravity", c->gravity, "gravity in the base frame [m/s^2]")
      ->default_val("0 0 -9.81");
  sub->add_option("--sg-order", c->sg_order, "Savitzky-Golay polynomial order for missing qd/qdd, 2 to 10")
      ->default_val("4");
  sub->add_option("--sg-window", c->sg_window, "Savitzky-Golay window [s] (the paper: 0.1)")->default_val("0.1");
  sub->add_flag("--skip-bad-rows", c->skip_bad_rows, "skip (and count) malformed rows instead of rejecting the file");
  sub->add_option("--predictions", c->predictions,
                  "write t and tau_hat_J for every sample of the validation data (or of the training data)");
  sub->add_option("--write-urdf", c->write_urdf,
                  "write the identified model as a URDF: links' <inertial>, viscous/coulomb as <dynamics damping friction>, "
                  "every other effect, rotor and payload in <inertial_effects> (validate --model reads it back)");
  sub->add_option("--time-scale", c->time_scale,
                  "multiply the time stamps of --data and --validate by this to get seconds (1e-3 for ms, 1e-9 for ns)");
  sub->add_option("--outlier-threshold", c->outlier_threshold,
                  "leave out training rows whose torque residual is beyond this many robust standard deviations "
                  "(0: chosen from the number of residuals, at least 5)")
      ->default_val("0");
  sub->add_flag("--no-outlier-rejection", c->no_outlier_rejection, "fit every training row, glitches included");
  sub->add_flag("--json", c->json, "print the result as JSON on stdout instead of the text report");
  return sub;
}

namespace {

// The fit's, the logs' and the outlier screening's settings; kOk, or the exit code (the error printed).
int ParseIdentifyOptions(const IdentifyCommand& c, JointIdentificationOptions* options, JointCsvOptions* csv,
                         OutlierOptions* outliers) {
  csv->skip_bad_rows = c.skip_bad_rows;
  int status = ParseRealOption(c.prior_weight, "--prior-weight", 0.0, 1e12, &options->prior_weight);
  if (status == kOk) status = ParseInteger(c.max_iterations, "--max-iterations", 1, 100000, &options->lm.max_iterations);
  if (status == kOk) status = ParseInteger(c.sg_order, "--sg-order", 2, 10, &csv->differentiation.order);
  if (status == kOk) status = ParseRealOption(c.sg_window, "--sg-window", 1e-6, 1e6, &csv->differentiation.window);
  if (status == kOk && !c.time_scale.empty()) {
    status = ParseRealOption(c.time_scale, "--time-scale", 1e-15, 1e6, &csv->time_scale);
  }
  outliers->enabled = !c.no_outlier_rejection;
  if (status == kOk) status = ParseRealOption(c.outlier_threshold, "--outlier-threshold", 0.0, 1e6, &outliers->threshold);
  if (status == kOk && outliers->threshold > 0 && outliers->threshold < 3) {
    std::cerr << "Error: --outlier-threshold: " << c.outlier_threshold
              << " robust standard deviations would leave out good rows (a Gaussian residual exceeds 3 once in 370); "
                 "give 3 or more, or 0 for the automatic choice\n";
    status = kUsage;
  }
  return status;
}

// Fits with its progress on stderr; kInvalidValue (the error printed) if there is nothing to fit.
int Fit(const std::string& data, const RobotDynamics& model, const JointSamples& train, const JointSamples* validation,
        JointIdentificationOptions options, const OutlierOptions& outliers, IdentificationRun* run) {
  try {
    Progress progress("identify");
    options.lm.progress = [&](int iteration, double cost) {
      progress.Show("iteration " + std::to_string(iteration) + ", cost " + std::to_string(cost));
    };
    *run = RunIdentification(model, train, validation, options, outliers);
    progress.Done();
  } catch (const std::invalid_argument& e) {
    std::cerr << "Error: " << data << ": " << e.what() << "\n";
    return kInvalidValue;
  }
  return kOk;
}

// --predictions (of `predicted`) and --write-urdf: the identified model as a model file
// (model_file.hpp), so that `validate --model` of it predicts what the fit predicts. kOk, or the
// exit code (the error printed).
int WriteOutputs(const IdentifyCommand& c, const RobotModel& robot, const RobotDynamics& model,
                 const IdentificationRun& run, const JointSamples& predicted, const std::vector<ModelEffect>& gains) {
  try {
    if (!c.predictions.empty()) WriteTorquePredictions(c.predictions, model, run.fit.x, predicted);
    if (c.write_urdf.empty()) return kOk;
    ModelSnapshot snapshot = SnapshotAt(model, run.fit.x);
    if (run.uncertainty) snapshot.notes = UncertaintyNotes(model, snapshot, FromFit(*run.uncertainty));
    AddPlausibilityNotes(model, snapshot.bodies, &snapshot.notes);
    snapshot.measurement = gains;
    WriteModelUrdf(c.model, c.write_urdf, robot, model, snapshot, "identified from " + RunsName(c.data));
    std::cerr << "wrote " << c.write_urdf << ": " << model.bodies().size() << " bodies, " << model.effects().size()
              << " joint effect terms\n";
  } catch (const CsvError& e) {
    std::cerr << "Error: " << e.what() << "\n";
    return ExitCodeOf(e);
  } catch (const UrdfError& e) {
    std::cerr << "Error: " << e.what() << "\n";
    return kIoError;
  }
  return kOk;
}

// The DOFs whose log is to be scaled by a fitted gain (gain@joint among the effects), ascending.
std::vector<int> GainDofs(const RobotModel& robot, const std::vector<EffectSpec>& effects) {
  std::vector<int> dofs;
  for (const EffectSpec& e : effects) {
    if (e.kind != EffectKind::kGain) continue;
    for (int d = 0; d < static_cast<int>(robot.dof_names.size()); ++d) {
      if ((e.target.empty() || robot.dof_names[static_cast<size_t>(d)] == e.target) &&
          std::find(dofs.begin(), dofs.end(), d) == dofs.end()) {
        dofs.push_back(d);
      }
    }
  }
  std::sort(dofs.begin(), dofs.end());
  return dofs;
}

// gain@joint (gain_identification.hpp): the gains fitted with the links, then every gain joint's
// log turned into N m (train: minus what known payloads add; validation: the log alone), so that the
// identification below fits torques. kOk, or the exit code (the error printed).
int FitGains(const RobotDynamics& model, const JointIdentificationOptions& options, const std::vector<int>& dofs,
             const Eigen::MatrixXd& known, JointSamples* train, JointSamples* validation, GainIdentificationResult* gains) {
  if (const std::optional<std::string> why = GainScaleProblem(model, known, dofs, options.frozen_bodies)) {
    std::cerr << "Error: gain@: " << *why << "\n";
    return kUsage;
  }
  try {
    *gains = IdentifyWithGains(model, AccumulateGainProblem(model, *train, known, dofs), options);
  } catch (const std::invalid_argument& e) {
    std::cerr << "Error: " << e.what() << "\n";
    return kInvalidValue;
  }
  for (size_t g = 0; g < dofs.size(); ++g) {
    const int d = dofs[g];
    const double gain = gains->gains[static_cast<Eigen::Index>(g)];
    train->tau.col(d) = train->tau.col(d) / gain - known.col(d);
    if (validation->size() > 0) validation->tau.col(d) /= gain;
  }
  return kOk;
}

// "Gains of the logged torques (log unit per N m, fitted with the links): knee 12.01 +- 0.02, ...".
std::string GainsText(const RobotDynamics& model, const std::vector<int>& dofs, const GainIdentificationResult& g) {
  std::string text = "Gains of the logged torque columns (log unit per N m, fitted with the links):";
  for (size_t k = 0; k < dofs.size(); ++k) {
    text += (k == 0 ? " " : ", ") + model.dof_names()[static_cast<size_t>(dofs[k])] + " " +
            FormatNumber(g.gains[static_cast<Eigen::Index>(k)], 6);
  }
  return text + "\n";
}

std::vector<ModelEffect> GainEffects(const RobotDynamics& model, const std::vector<int>& dofs, const GainIdentificationResult& g) {
  std::vector<ModelEffect> out;
  for (size_t k = 0; k < dofs.size(); ++k) {
    ModelEffect m;
    m.spec.kind = EffectKind::kGain;
    m.spec.target = model.dof_names()[static_cast<size_t>(dofs[k])];
    m.spec.text = "gain@" + m.spec.target;
    m.values = {g.gains[static_cast<Eigen::Index>(k)]};
    out.push_back(m);
  }
  return out;
}

// Each --run-payload's body as used: stated, or fitted with the model (mass, COM and inertia about
// the COM in its link's frame).
nlohmann::json RunPayloadsJson(const std::vector<RunPayload>& payloads) {
  nlohmann::json out = nlohmann::json::array();
  for (const RunPayload& p : payloads) {
    const Vector3 c = p.body.com();
    const Matrix3 I = p.body.rotational_inertia_about_com();
    out.push_back({{"run", p.file},
                   {"link", p.link},
                   {"fitted", p.fitted},
                   {"mass_stated", p.mass_known},
                   {"mass", p.body.mass()},
                   {"com", {c.x(), c.y(), c.z()}},
                   {"inertia", {I(0, 0), I(1, 1), I(2, 2), I(0, 1), I(0, 2), I(1, 2)}}});
  }
  return out;
}

}  // namespace

int RunIdentifyCommand(const IdentifyCommand& c) {
  std::vector<PathOption> inputs{{"--model", c.model}, {"--validate", c.validate}};
  for (const std::string& d : c.data) inputs.push_back({"--data", d});
  int status = RefuseOverwritingInputs({{"--predictions", c.predictions}, {"--write-urdf", c.write_urdf}}, inputs);
  JointIdentificationOptions options;
  JointCsvOptions csv;
  OutlierOptions outliers;
  if (status == kOk) status = ParseIdentifyOptions(c, &options, &csv, &outliers);
  Vector3 gravity;
  if (status == kOk) status = ParseGravityOption(c.gravity, &gravity);
  RobotModel robot;
  std::vector<EffectSpec> effects;
  std::optional<RobotDynamics> model;
  if (status == kOk) status = LoadRobot(c.model, c.effects, gravity, &robot, &effects, &model);
  std::vector<UserRegion> regions;
  if (status == kOk) status = ParseRegionOptions(c.regions, &regions);
  if (status == kOk) status = ApplyRegionOptions(robot, regions, &*model);
  if (status == kOk) status = ParseTotalMassOption(c.total_mass, robot, *model, false, &options.total_mass);
  std::vector<RunPayload> payloads;
  if (status == kOk) status = ParseRunPayloads(c.run_payloads, c.data, &payloads);
  RecordedRuns runs;
  JointSamples validation;
  std::vector<int> train_lines;
  Eigen::MatrixXd known;  // known payloads' torques on the joints whose gain is fitted
  LogGains log_gains;
  log_gains.fitted = GainDofs(robot, effects);
  log_gains.known = &known;
  RunPayloadFit payload_fit;  // payloads without a COM: fitted with the model, then known
  payload_fit.effects = effects;
  payload_fit.options = options;
  payload_fit.regions = regions;
  if (status == kOk) {
    status = ReadRobotRuns(c.data, &payloads, robot, gravity, csv, &runs, &train_lines, log_gains, &payload_fit);
  }
  if (status == kOk && !c.validate.empty()) status = ReadRobotLog(c.validate, robot, csv, &validation);
  std::optional<GainIdentificationResult> gains;
  if (status == kOk && !log_gains.fitted.empty()) {
    gains.emplace();
    status = FitGains(*model, options, log_gains.fitted, known, &runs.samples, &validation, &*gains);
  }
  if (status != kOk) return status;
  const JointSamples& train = runs.samples;
  const std::string data = RunsName(c.data);
  if (train.size() < 2) {
    std::cerr << "Error: " << data << ": " << train.size() << " samples; identification needs more\n";
    return kInvalidValue;
  }
  IdentificationRun run;
  outliers.run_starts = runs.starts;  // each run screened by its own spread
  status = Fit(data, *model, train, c.validate.empty() ? nullptr : &validation, options, outliers, &run);
  if (status != kOk) return status;
  NameSamplesByLine(c.data, runs.starts, train_lines, &run.outliers.reasons);  // rejected rows by their file and line
  if (run.failed()) {
    std::cerr << FitFailureText(data, run, train, outliers.enabled);
    return kInvalidValue;
  }
  // Several runs: the fit's error on each (every sample of it, rows the screening left out included).
  const std::vector<ModelComparison> per_run =
      runs.num_runs() > 1 ? CompareJointModelByRun(*model, run.fit.x, runs) : std::vector<ModelComparison>{};
  // The links' total against the robot as weighed (--total-mass), with the body plausibility.
  std::optional<TotalMassPlausibility> total;
  if (options.total_mass) total = JudgeTotalMass(*model, run.fit.x, *options.total_mass);
  if (c.json) {
    nlohmann::json j = IdentificationJson(*model, run);
    if (!per_run.empty()) j["runs"] = RunErrorsJson(runs.names, per_run);
    if (!payloads.empty()) j["run_payloads"] = RunPayloadsJson(payloads);
    if (total) {
      j["total_mass"] = TotalMassJson(*total);
      if (!total->within) j["plausible"] = false;
    }
    if (gains) {
      for (size_t k = 0; k < log_gains.fitted.size(); ++k) {
        j["gains"][model->dof_names()[static_cast<size_t>(log_gains.fitted[k])]] = {
            {"g", gains->gains[static_cast<Eigen::Index>(k)]}};
      }
    }
    std::cout << j.dump(2) << "\n";
  } else {
    std::cout << IdentificationText(*model, run) << (total ? TotalMassText(*total) + TotalMassWarning(*total) : "")
              << RunErrorsText(runs.names, per_run, "The fit's error on the training runs")
              << (gains ? GainsText(*model, log_gains.fitted, *gains) : "");
  }
  status = WriteOutputs(c, robot, *model, run, c.validate.empty() ? train : validation,
                        gains ? GainEffects(*model, log_gains.fitted, *gains) : std::vector<ModelEffect>{});
  if (status == kOk && !run.fit.lm.converged()) {
    std::cerr << "warning: the fit stopped on " << ToString(run.fit.lm.reason) << " after " << run.fit.lm.iterations
              << " iterations without converging (raise --max-iterations or --prior-weight)\n";
  }
  return status;
}

}  // namespace inertial::cli
