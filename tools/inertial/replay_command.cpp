// `inertial replay`: an lcm-logger log (or a joint CSV) through the online estimator inertiald
// runs, as fast as the machine allows or in real time (log_replay.hpp).
#include <fstream>
#include <iostream>

#include "commands.hpp"
#include "exit_codes.hpp"
#include "inertial/config/daemon_config.hpp"
#include "inertial/config/motors_yaml.hpp"
#include "inertial/runtime/log_replay.hpp"
#include "inertial/formats/file_error.hpp"
#include "inertial/transport/can_joint_assembler.hpp"
#include "inertial/formats/model_file.hpp"
#include "inertial/report/uncertainty_report.hpp"
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
  sub->add_option("--channel", c->channel, "joint-state channel (default INERTIAL_JOINT_STATE, or the config's)");
  sub->add_option("--config", c->config, "inertiald's JSON config (its channel and message format are used)");
  sub->add_option("--out", c->out, "estimates as CSV: t, counts, per body mass and COM, effects, residuals");
  sub->add_option("--write-log", c->write_log, "estimates as an LCM log of inertial.estimate_t");
  sub->add_option("--write-urdf", c->write_urdf,
                  "the final estimate as a model file (URDF with links, effects, rotors, payloads) for validate --model");
  sub->add_option("--estimator", c->estimator, "gauss_newton, gradient or linear_rls (default: --config's or gauss_newton)");
  sub->add_option("--noise-tau", c->noise_tau,
                  "torque noise standard deviation the estimator assumes [N m] (default: --config's or 1)");
  sub->add_option("--publish-rate", c->publish_rate,
                  "estimates per second of log time (rows of --out and --write-log) [Hz] (default: --config's or 10)");
  sub->add_option("--time-scale", c->time_scale,
                  "joint CSV logs: multiply the time stamps by this to get seconds (1e-3 for ms, 1e-9 for ns)");
  sub->add_flag("--realtime", c->realtime, "follow the log's time stamps instead of running as fast as possible");
  return sub;
}

namespace {

// A replay that gave the estimator nothing is a failure, not a final estimate equal to the prior:
// say why, and for an LCM log which channels it does have.
int NothingReplayed(const std::string& path, const ReplayOptions& options, const ReplayResult& r) {
  std::cerr << "Error: replay: " << path << " gave the estimator no sample: ";
  if (options.can) {
    if (r.counters.received == 0) {
      std::cerr << "of its " << r.events << " lines none is a candump frame";
    } else {
      std::cerr << "its " << r.counters.received << " frame lines made " << r.samples << " complete ticks ("
                << RejectionsText(r.counters) << "): check --can-config's ids and window";
    }
  } else if (path.size() >= 4 && path.compare(path.size() - 4, 4, ".csv") == 0) {
    std::cerr << "every one of its " << r.counters.received << " samples was refused: " << RejectionsText(r.counters);
  } else if (r.counters.received == 0) {
    std::cerr << "no message on channel " << options.channel << ";";
    if (r.channels.empty()) std::cerr << " it has no channel at all";
    for (const auto& [channel, count] : r.channels) std::cerr << " " << channel << " (" << count << " messages)";
    std::cerr << "; choose one with --channel";
  } else {
    std::cerr << "every one of the " << r.counters.received << " messages on " << options.channel
              << " was refused: " << RejectionsText(r.counters);
    if (r.counters[Rejection::kUnknownJoint] != 0) std::cerr << " (the messages name joints the --model does not have)";
  }
  std::cerr << "\n";
  return kNoData;
}

}  // namespace

int RunReplayCommand(const ReplayCommand& c) {
  int status = RefuseOverwritingInputs(
      {{"--out", c.out}, {"--write-log", c.write_log}, {"--write-urdf", c.write_urdf}},
      {{"--model", c.model}, {"--log", c.log}, {"--candump", c.candump}, {"--can-config", c.can_config}, {"--config", c.config}});
  if (status != kOk) return status;
  OnlineEstimatorOptions estimator_options;
  ReplayOptions options;
  if (c.log.empty() == c.candump.empty()) {
    std::cerr << "Error: give --log FILE or --candump FILE, not " << (c.log.empty() ? "neither" : "both") << "\n";
    return kUsage;
  }
  if (c.candump.empty() != c.can_config.empty()) {
    std::cerr << "Error: --candump and --can-config go together\n";
    return kUsage;
  }
  if (!c.can_config.empty()) {
    try {
      options.can = LoadCanConfig(c.can_config);
    } catch (const std::exception& e) {  // cannot be read, or not a valid motors.yaml: a file error
      std::cerr << "Error: --can-config: " << e.what() << "\n";
      return kIoError;
    }
  }
  const std::string& path = c.candump.empty() ? c.log : c.candump;
  // inertiald's --config first (its channel, message format, estimator, noise and tuning, so that the
  // replay runs the daemon's estimator), then the command line's options over it.
  if (!c.config.empty()) {
    std::ifstream in(c.config);
    if (!in) {
      std::cerr << "Error: --config: " << CannotText("read", "configuration", c.config) << "\n";
      return kIoError;
    }
    try {
      DaemonOptions daemon;
      daemon.input_channel = options.channel;
      ApplyDaemonConfig(nlohmann::json::parse(in), &daemon);
      options.channel = daemon.input_channel;
      options.format = daemon.format;
      estimator_options = daemon.estimator;
      options.estimate_period_s = 1.0 / daemon.publish_rate_hz;
      options.residual_window_s = daemon.residual_window_s;
    } catch (const std::exception& e) {  // not JSON, or not a valid configuration: a file error
      std::cerr << "Error: --config: " << c.config << ": " << e.what() << "\n";
      return kIoError;
    }
  }
  if (!c.noise_tau.empty()) {
    status = ParseRealOption(c.noise_tau, "--noise-tau", 1e-12, 1e12, &estimator_options.measurement_sigma);
  }
  if (status == kOk && !c.publish_rate.empty()) {
    double publish_rate = 10.0;
    status = ParseRealOption(c.publish_rate, "--publish-rate", 1e-9, 1e9, &publish_rate);
    options.estimate_period_s = 1.0 / publish_rate;
  }
  if (status == kOk && !c.time_scale.empty()) {
    status = ParseRealOption(c.time_scale, "--time-scale", 1e-15, 1e6, &options.csv.time_scale);
  }
  if (status != kOk) return status;
  if (!c.estimator.empty()) {
    try {
      estimator_options.kind = ParseEstimatorKind(c.estimator);
    } catch (const std::invalid_argument& e) {
      std::cerr << "Error: --estimator: " << e.what() << "\n";
      return kUsage;
    }
  }
  if (!c.channel.empty()) options.channel = c.channel;
  options.realtime = c.realtime;
  options.csv_path = c.out;
  options.log_path = c.write_log;
  RobotModel robot;
  std::vector<EffectSpec> effects;
  std::optional<RobotDynamics> model;
  status = LoadRobot(c.model, c.effects, Vector3(0, 0, -9.81), &robot, &effects, &model);
  if (status != kOk) return status;
  if (options.can) {
    try {  // the motors must cover the model's joints: a settings file that does not fit, a file error
      const CanJointAssembler check(*options.can, model->dof_names());
    } catch (const std::invalid_argument& e) {
      std::cerr << "Error: --can-config: " << c.can_config << ": " << e.what() << "\n";
      return kIoError;
    }
  }
  OnlineJointEstimator estimator(*model, Eigen::VectorXd::Zero(model->num_parameters()), estimator_options);
  ReplayResult r;
  try {
    r = ReplayLog(path, &estimator, options);
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
  const std::string reasons = RejectionsText(r.counters);
  std::cout << "replayed " << path << ": " << r.events << (options.can ? " lines, " : " events, ") << r.counters.received
            << (options.can ? " frame lines" : " on " + options.channel) << "; accepted " << r.counters.accepted
            << ", rejected " << r.counters.total_rejected() << (reasons.empty() ? "" : " (" + reasons + ")");
  if (options.can) {
    std::cout << "\nCAN: " << r.samples << " complete ticks; " << r.lines_not_frames << " lines that are not frames";
  }
  std::cout << "\nthroughput: " << static_cast<long long>(r.samples_per_second) << " samples/s (" << r.seconds
            << " s)\n";
  if (r.counters.accepted == 0) return NothingReplayed(path, options, r);
  const std::optional<ModelUncertainty> uncertainty = FromOnlineEstimator(estimator);
  std::cout << "final estimate" << (uncertainty ? " (+- one standard deviation " + uncertainty->source + ")" : "") << ":\n";
  for (int e = 0; e < static_cast<int>(model->bodies().size()); ++e) {
    const InertialParams b = estimator.Body(e);
    if (uncertainty) {
      std::cout << "  " << model->bodies()[e].name << ": " << BodyUncertaintyText(b, uncertainty->bodies[e], nullptr)
                << "\n";
    } else {
      std::cout << "  " << model->bodies()[e].name << ": mass " << b.mass() << " kg, COM [" << b.com().transpose()
                << "] m\n";
    }
  }
  if (!c.write_urdf.empty()) {
    try {
      WriteModelUrdf(c.model, c.write_urdf, robot, *model, SnapshotWithUncertainty(estimator),
                     "the online estimate after replaying " + path + " (" + std::to_string(r.counters.accepted) +
                         " samples, " + std::string(ToString(estimator.kind())) + ")");
    } catch (const std::invalid_argument& e) {
      std::cerr << "Error: --write-urdf: " << e.what() << "\n";
      return kInconsistentBody;
    } catch (const UrdfError& e) {
      std::cerr << "Error: " << e.what() << "\n";
      return kIoError;
    }
    std::cerr << "wrote " << c.write_urdf << ": the final estimate as a model file\n";
  }
  if (!c.out.empty()) std::cerr << "wrote " << c.out << ": " << r.estimate_rows << " rows\n";
  if (!c.write_log.empty()) std::cerr << "wrote " << c.write_log << ": " << r.estimate_rows << " estimates\n";
  return kOk;
}

}  // namespace inertial::cli
