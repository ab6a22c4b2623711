// `inertial replay`: an lcm-logger log (or a joint CSV) through the online estimator inertiald
// runs, as fast as the machine allows or in real time (log_replay.hpp).
#include <iostream>
#include <optional>

#include "commands.hpp"
#include "exit_codes.hpp"
#include "inertial/config/motors_yaml.hpp"
#include "inertial/diagnosis/payload_event.hpp"
#include "inertial/formats/model_file.hpp"
#include "inertial/report/identification_report.hpp"
#include "inertial/report/online_diagnosis_report.hpp"
#include "inertial/report/online_estimate_text.hpp"
#include "inertial/report/payload_report.hpp"
#include "inertial/report/uncertainty_report.hpp"
#include "inertial/runtime/log_replay.hpp"
#include "inertial/runtime/replay_config.hpp"
#include "inertial/runtime/replay_summary.hpp"
#include "inertial/diagnosis/stream_diagnosis.hpp"
#include "inertial/transport/can_joint_assembler.hpp"
#include "option_parsing.hpp"
#include "robot_inputs.hpp"

namespace inertial::cli {

CLI::App* AddReplayCommand(CLI::App& app, ReplayCommand* c) {
  CLI::App* sub = app.add_subcommand(
      "replay",
      "Replay a recorded log through the online estimator of inertiald: an lcm-logger log (the joint-state messages "
      "of one channel), a joint CSV (a .csv file), or a candump -l log of motor frames (--candump with --can-config). Writes the estimate trajectory (--out CSV, --write-log LCM) and "
      "prints the throughput.");
  sub->add_option("--model", c->model, "URDF robot description")->required();
  sub->add_option("--log", c->log, "lcm-logger log, or a joint CSV (.csv)");
  sub->add_option("--candump", c->candump, "a candump -l log of motor-driver frames (with --can-config)");
  sub->add_option("--can-config", c->can_config, "motors.yaml: which frames are which joint's, and how to decode them");
  sub->add_option("--effects", c->effects, "effects beyond rigid links (syntax of identify --effects)");
  sub->add_option("--region", c->regions, kRegionHelp);
  sub->add_option("--channel", c->channel, "joint-state channel (default INERTIAL_JOINT_STATE, or the config's)");
  sub->add_option("--config", c->config, "inertiald's JSON config (its channel and message format are used)");
  sub->add_option("--out", c->out, "estimates as CSV: t, counts, per body mass and COM, effects, residuals");
  sub->add_option("--write-log", c->write_log, "estimates as an LCM log of inertial.estimate_t");
  sub->add_option("--write-urdf", c->write_urdf,
                  "the final estimate as a model file (URDF with links, effects, rotors, payloads) for validate --model");
  sub->add_option("--estimator", c->estimator, "gauss_newton (the online fit: the batch objective re-solved from its statistics), ekf (the extended Kalman filter on the parameters), gradient or linear_rls (default: --config's or gauss_newton)");
  sub->add_option("--noise-tau", c->noise_tau,
                  "torque noise standard deviation the estimator assumes [N m] (default: --config's or 1)");
  sub->add_option("--publish-rate", c->publish_rate,
                  "estimates per second of log time (rows of --out and --write-log) [Hz] (default: --config's or 10)");
  sub->add_option("--time-scale", c->time_scale,
                  "joint CSV logs: multiply the time stamps by this to get seconds (1e-3 for ms, 1e-9 for ns)");
  sub->add_flag("--realtime", c->realtime, "follow the log's time stamps instead of running as fast as possible");
  sub->add_flag("--diagnose", c->diagnose,
                "judge every candidate effect on the stream as it is replayed (each sample predicted before it is "
                "learned from) and end with the ranked missing effects");
  sub->add_flag("--json", c->json, "print the summary (and with --diagnose the diagnosis) as JSON on stdout");
  return sub;
}

namespace {

// The numeric and named options over the configuration; the error printed and its exit code returned.
int ParseReplayOverrides(const ReplayCommand& c, ReplayOverrides* o) {
  double value = 0.0;
  int status = kOk;
  if (!c.noise_tau.empty() && (status = ParseRealOption(c.noise_tau, "--noise-tau", 1e-12, 1e12, &value)) == kOk) {
    o->noise_tau = value;
  }
  if (status == kOk && !c.publish_rate.empty() &&
      (status = ParseRealOption(c.publish_rate, "--publish-rate", 1e-9, 1e9, &value)) == kOk) {
    o->publish_rate_hz = value;
  }
  if (status == kOk && !c.time_scale.empty() &&
      (status = ParseRealOption(c.time_scale, "--time-scale", 1e-15, 1e6, &value)) == kOk) {
    o->time_scale = value;
  }
  if (status != kOk) return status;
  if (!c.estimator.empty()) {
    try {
      o->estimator = ParseEstimatorKind(c.estimator);
    } catch (const std::invalid_argument& e) {
      std::cerr << "Error: --estimator: " << e.what() << "\n";
      return kUsage;
    }
  }
  o->channel = c.channel;
  o->realtime = c.realtime;
  o->csv_path = c.out;
  o->log_path = c.write_log;
  return kOk;
}

// --can-config, inertiald's --config, then the command line's options over them.
int ConfigureReplay(const ReplayCommand& c, ReplayConfig* config) {
  std::optional<CanConfig> can;
  if (!c.can_config.empty()) {
    try {
      can = LoadCanConfig(c.can_config);
    } catch (const std::exception& e) {  // cannot be read, or not a valid motors.yaml: a file error
      std::cerr << "Error: --can-config: " << e.what() << "\n";
      return kIoError;
    }
  }
  try {
    *config = ReplayConfigFromFile(c.config);
  } catch (const std::runtime_error& e) {
    std::cerr << "Error: " << e.what() << "\n";
    return kIoError;
  }
  config->replay.can = std::move(can);
  ReplayOverrides overrides;
  const int status = ParseReplayOverrides(c, &overrides);
  if (status == kOk) ApplyReplayOverrides(overrides, config);
  return status;
}

// The motors must cover the model's joints: a settings file that does not fit, a file error.
int CheckMotorsFitModel(const ReplayCommand& c, const ReplayOptions& options, const RobotDynamics& model) {
  if (!options.can) return kOk;
  try {
    const CanJointAssembler check(*options.can, model.dof_names());
  } catch (const std::invalid_argument& e) {
    std::cerr << "Error: --can-config: " << c.can_config << ": " << e.what() << "\n";
    return kIoError;
  }
  return kOk;
}

// The log through the estimator; with `diagnosis`, each accepted sample and the estimator's residual
// before its update go to it (a detected change restarts its statistics); payload events into *events.

int Replay(const std::string& path, OnlineJointEstimator* estimator, const ReplayOptions& options, ReplayResult* r,
           StreamDiagnosis* diagnosis, std::vector<PayloadEvent>* events) {
  try {
    PayloadEventDetector detector(*estimator);
    std::uint64_t changes = estimator->estimator().changes_detected();
    const std::function<void(const Sample&, SamplePipeline::Outcome)> observe =
        [&](const Sample& s, SamplePipeline::Outcome outcome) {
          if (outcome.rejection != Rejection::kNone) return;
          if (std::optional<PayloadEvent> e = detector.Observe(*estimator, s.joint)) events->push_back(std::move(*e));
          if (diagnosis == nullptr) return;
          if (estimator->estimator().changes_detected() != changes) {
            changes = estimator->estimator().changes_detected();
            diagnosis->Reset();
          }
          if (outcome.accepted()) diagnosis->Observe(s.joint, estimator->stream_residual());
        };
    *r = ReplayLog(path, estimator, options, observe);
    // A change confirmed but still settling when the log ends is concluded on what the log held.
    if (std::optional<PayloadEvent> e = detector.Flush(*estimator)) events->push_back(std::move(*e));
  } catch (const CsvError& e) {
    std::cerr << "Error: " << e.what() << "\n";
    return ExitCodeOf(e);
  } catch (const std::runtime_error& e) {
    std::cerr << "Error: " << e.what() << "\n";
    return kIoError;
  } catch (const std::invalid_argument& e) {
    std::cerr << "Error: " << e.what() << "\n";
    return kUsage;
  }
  return kOk;
}

int WriteFinalModel(const ReplayCommand& c, const std::string& path, const RobotModel& robot,
                    const OnlineJointEstimator& estimator, const ReplayResult& r) {
  try {
    WriteModelUrdf(c.model, c.write_urdf, robot, estimator.model(), SnapshotWithUncertainty(estimator),
                   ReplayEstimateOrigin(path, r.counters.accepted, ToString(estimator.kind())));
  } catch (const std::invalid_argument& e) {
    std::cerr << "Error: --write-urdf: " << e.what() << "\n";
    return kInconsistentBody;
  } catch (const UrdfError& e) {
    std::cerr << "Error: " << e.what() << "\n";
    return kIoError;
  }
  std::cerr << "wrote " << c.write_urdf << ": the final estimate as a model file\n";
  return kOk;
}

// Refuses outputs that would overwrite an input, and a wrong choice of log (--log or --candump with
// --can-config). Returns kOk or the exit status.
int CheckReplayInputs(const ReplayCommand& c) {
  const int status = RefuseOverwritingInputs(
      {{"--out", c.out}, {"--write-log", c.write_log}, {"--write-urdf", c.write_urdf}},
      {{"--model", c.model}, {"--log", c.log}, {"--candump", c.candump}, {"--can-config", c.can_config}, {"--config", c.config}});
  if (status != kOk) return status;
  if (c.log.empty() == c.candump.empty()) {
    std::cerr << "Error: give --log FILE or --candump FILE, not " << (c.log.empty() ? "neither" : "both") << "\n";
    return kUsage;
  }
  if (c.candump.empty() != c.can_config.empty()) {
    std::cerr << "Error: --candump and --can-config go together\n";
    return kUsage;
  }
  return kOk;
}

// The payload events as a JSON array.
nlohmann::json PayloadEventsJson(const std::vector<PayloadEvent>& events) {
  nlohmann::json events_json = nlohmann::json::array();
  for (const PayloadEvent& e : events) {
    events_json.push_back({{"onset_time", e.onset_time},
                           {"detection_time", e.detection_time},
                           {"settle_time", e.settle_time},
                           {"settled", e.settled},
                           {"link", e.link},
                           {"added_mass", e.added_mass},
                           {"added_mass_std", e.added_mass_std},
                           {"com", {e.com[0], e.com[1], e.com[2]}},
                           {"com_std", {e.com_std[0], e.com_std[1], e.com_std[2]}},
                           {"text", PayloadEventText(e)}});
    // A pick-up as the controllers load it (payload_report.hpp), in the event link's frame.
    if (const std::optional<PayloadValues> p = PayloadValuesOf(e)) {
      events_json.back()["ur_script"] = UrScriptPayload(*p);
      events_json.back()["franka"] = FrankaSetLoad(*p);
    }
  }
  return events_json;
}

// Prints the replay's outcome as JSON (--json): counters, diagnosis, payload events, final estimate.
void PrintReplayJson(const std::string& path, const ReplayResult& r, const std::optional<StreamJudgement>& judged,
                     const std::vector<PayloadEvent>& events, const OnlineJointEstimator& estimator) {
  nlohmann::json events_json = PayloadEventsJson(events);
  nlohmann::json j = {{"log", path},
                      {"received", r.counters.received},
                      {"accepted", r.counters.accepted},
                      {"rejected", r.counters.total_rejected()},
                      {"samples_per_second", r.samples_per_second}};
  if (judged) {
    const nlohmann::json d = OnlineDiagnosisJson(judged->diagnosis);
    j["suggestions"] = d["suggestions"];
    j["diagnosis"] = d;
    if (judged->excitation) {
      j["unexcited"] = UnexcitedNames(*judged->excitation, false);
      j["unexcited_since_start"] = UnexcitedNames(*judged->excitation, true);
      j["excitation"] = UnexcitedText(*judged->excitation);
    }
  }
  j["payload_events"] = events_json;
  j["estimate"] = OnlineEstimateJson(estimator);
  std::cout << j.dump(2) << "\n";
}

// Prints the replay's outcome as text: the summary, the estimate, payload events, diagnosis.
void PrintReplayText(const std::string& path, const ReplayOptions& options, const ReplayResult& r,
                     const std::optional<StreamJudgement>& judged, const std::vector<PayloadEvent>& events,
                     const OnlineJointEstimator& estimator) {
  std::cout << ReplaySummaryText(path, options, r);
  std::cout << OnlineEstimateText(estimator);
  for (const PayloadEvent& e : events) {
    std::cout << PayloadEventText(e) << "\n";
    if (const std::optional<PayloadValues> p = PayloadValuesOf(e)) {
      std::cout << "  in " << e.link << "'s frame, URScript: " << UrScriptPayload(*p) << "\n  Franka: " << FrankaSetLoad(*p)
                << "\n";
    }
  }
  if (judged) {
    std::cout << OnlineDiagnosisText(judged->diagnosis);
    if (judged->excitation) std::cout << "Excitation: " << UnexcitedText(*judged->excitation) << "\n";
  }
}

}  // namespace

int RunReplayCommand(const ReplayCommand& c) {
  int status = CheckReplayInputs(c);
  if (status != kOk) return status;
  const std::string& path = c.candump.empty() ? c.log : c.candump;
  ReplayConfig config;
  if ((status = ConfigureReplay(c, &config)) != kOk) return status;
  RobotModel robot;
  std::vector<EffectSpec> effects;
  std::optional<RobotDynamics> model;
  status = LoadRobot(c.model, c.effects, Vector3(0, 0, -9.81), &robot, &effects, &model);
  std::vector<UserRegion> regions;
  if (status == kOk) status = ParseRegionOptions(c.regions, &regions);
  if (status == kOk) status = ApplyRegionOptions(robot, regions, &*model);
  if (status == kOk) status = CheckMotorsFitModel(c, config.replay, *model);
  if (status != kOk) return status;
  config.replay.log_gains = StatedLogGains(robot, robot.effects);  // a log of currents, in N m first
  OnlineJointEstimator estimator(*model, Eigen::VectorXd::Zero(model->num_parameters()), config.estimator);
  ReplayResult r;
  std::optional<StreamDiagnosis> diagnosis;
  if (c.diagnose) {
    StreamDiagnosisOptions options = StreamDiagnosisOptionsFor(*model, config.estimator);
    options.threaded = false;  // a replay's diagnosis does not depend on scheduling
    diagnosis.emplace(*model, options);
  }
  std::vector<PayloadEvent> events;
  if ((status = Replay(path, &estimator, config.replay, &r, diagnosis ? &*diagnosis : nullptr, &events)) != kOk) {
    return status;
  }
  if (r.counters.accepted == 0) {
    if (!c.json) std::cout << ReplaySummaryText(path, config.replay, r);
    std::cerr << "Error: " << NothingReplayedText(path, config.replay, r) << "\n";
    return kNoData;
  }
  std::optional<StreamJudgement> judged;
  if (diagnosis) judged = diagnosis->EvaluateNow(BodyStatesOf(estimator), estimator.estimator().parameters());
  if (c.json) {
    PrintReplayJson(path, r, judged, events, estimator);
  } else {
    PrintReplayText(path, config.replay, r, judged, events, estimator);
  }
  if (!c.write_urdf.empty() && (status = WriteFinalModel(c, path, robot, estimator, r)) != kOk) return status;
  if (!c.out.empty()) std::cerr << "wrote " << c.out << ": " << r.estimate_rows << " rows\n";
  if (!c.write_log.empty()) std::cerr << "wrote " << c.write_log << ": " << r.estimate_rows << " estimates\n";
  return kOk;
}

}  // namespace inertial::cli
