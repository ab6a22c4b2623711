// inertiald: the online estimator beside the controller. Reads joint-state messages from LCM,
// updates the log-Cholesky estimate every sample, publishes inertial.estimate_t at a fixed rate,
// checkpoints its state, and stops cleanly on SIGINT or SIGTERM (estimation_daemon.hpp).
#include <CLI/CLI.hpp>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>

#include "command_line.hpp"
#include "numeric_options.hpp"
#include "inertial/config/motors_yaml.hpp"
#include "inertial/runtime/estimation_daemon.hpp"
#include "inertial/formats/file_error.hpp"
#include "inertial/formats/model_file.hpp"
#include "inertial/report/uncertainty_report.hpp"
#include "inertial/formats/number_parsing.hpp"

namespace {

std::atomic<bool> g_stop{false};
std::atomic<bool> g_write_model{false};

extern "C" void OnSignal(int) { g_stop = true; }
extern "C" void OnWriteSignal(int) { g_write_model = true; }

}  // namespace

int main(int argc, char** argv) {
  using namespace inertial;
  CLI::App app{
      "inertiald: online, physically consistent inertia estimation beside the controller. Subscribes to joint-state "
      "messages on LCM (inertial.joint_state_t, or the user's own type described in --config), runs the recursive "
      "estimator on every sample and publishes inertial.estimate_t. Exit codes: 0 ok, 1 LCM failure, 2 usage, "
      "5 a file error (model, config, motors.yaml: unreadable or not valid)."};
  std::string model_path, effects, config_path, lcm_url, channel, estimate_channel, residual_channel, checkpoint;
  std::string estimator = "", log_level = "", publish_rate = "", checkpoint_interval = "", noise_tau = "";
  bool body = false;
  std::string prior, write_urdf;
  app.add_option("--model", model_path, "URDF robot description (robots)");
  app.add_flag("--body", body,
               "a single body on a wrench sensor: inertial.body_wrench_t messages (default channel INERTIAL_BODY_WRENCH)");
  app.add_option("--prior", prior, "--body: the prior body's pi, 10 numbers (default 1 kg, 1 kg m^2 at the origin)");
  std::string can_interface, can_config;
  app.add_option("--can", can_interface, "read the motors' frames from this SocketCAN interface (e.g. can0) instead of LCM");
  app.add_option("--can-config", can_config, "motors.yaml for --can: which frames are which joint's, and how to decode them");
  app.add_option("--effects", effects, "effects beyond rigid links (syntax of `inertial identify --effects`)");
  app.add_option("--config", config_path, "JSON configuration (channels, rates, checkpoint, message format)");
  app.add_option("--lcm-url", lcm_url, "LCM provider URL (default LCM's: udpm://239.255.76.67:7667)");
  app.add_option("--channel", channel, "joint-state channel (default INERTIAL_JOINT_STATE)");
  app.add_option("--estimate-channel", estimate_channel, "estimate channel (default INERTIAL_ESTIMATE)");
  app.add_option("--residual-channel", residual_channel, "publish inertial.residual_t per sample on this channel");
  app.add_option("--checkpoint", checkpoint, "estimator state file: restored at start, saved periodically and at exit");
  app.add_option("--checkpoint-interval", checkpoint_interval, "seconds between checkpoints (default 5)");
  bool fresh = false;
  app.add_flag("--fresh", fresh,
               "start from the priors even if --checkpoint names a file that cannot be restored (it is then "
               "overwritten); without it such a file stops the start and is left untouched");
  app.add_option("--publish-rate", publish_rate, "estimates per second (default 10)");
  app.add_option("--estimator", estimator, "gauss_newton (default), gradient or linear_rls");
  app.add_option("--noise-tau", noise_tau, "torque noise standard deviation the estimator assumes [N m] (default 1)");
  app.add_option("--write-urdf", write_urdf,
                 "write the current estimate as a model file (URDF: links, effects, rotors, payloads) at exit and on "
                 "SIGUSR1, for `inertial validate --model` or as the next prior");
  app.add_option("--log-level", log_level, "error, warn, info (default) or debug");
  app.name("inertiald");
  app.set_version_flag("--version", "inertiald " INERTIAL_VERSION);
  inertial::cli::DescribeNumericOptions(app);
  if (const std::optional<int> done = inertial::cli::ParseCommandLine(app, argc, argv, 2)) return *done;

  if (body == !model_path.empty()) {
    std::cerr << "Error: give --model URDF (a robot) or --body (a single body), not " << (body ? "both" : "neither") << "\n";
    return 2;
  }
  DaemonOptions options;
  if (body) options.input_channel = "INERTIAL_BODY_WRENCH";
  if (body && !write_urdf.empty()) {
    std::cerr << "Error: --write-urdf needs --model (a single body has no URDF; its estimate is in estimate_t)\n";
    return 2;
  }
  if (can_interface.empty() != can_config.empty() || (body && !can_interface.empty())) {
    std::cerr << "Error: --can and --can-config go together, with --model\n";
    return 2;
  }
  try {
    if (!config_path.empty()) {
      std::ifstream in(config_path);
      if (!in) {
        std::cerr << "Error: --config: " << CannotText("read", "configuration", config_path) << "\n";
        return 5;
      }
      nlohmann::json config;
      try {
        config = nlohmann::json::parse(in);
      } catch (const nlohmann::json::exception& e) {
        std::cerr << "Error: --config: " << config_path << " is not valid JSON: " << e.what() << "\n";
        return 5;
      }
      try {
        ApplyDaemonConfig(config, &options);
      } catch (const std::exception& e) {
        std::cerr << "Error: --config " << config_path << ": " << e.what() << "\n";
        return 5;  // a settings file that is not valid: a file error, as a bad URDF or motors.yaml
      }
    }
    if (!lcm_url.empty()) options.lcm_url = lcm_url;
    if (!channel.empty()) options.input_channel = channel;
    if (!estimate_channel.empty()) options.estimate_channel = estimate_channel;
    if (!residual_channel.empty()) options.residual_channel = residual_channel;
    if (!checkpoint.empty()) options.checkpoint_path = checkpoint;
    options.start_fresh = fresh;
    if (!estimator.empty()) options.estimator.kind = ParseEstimatorKind(estimator);
    if (!log_level.empty()) options.log_level = ParseLogLevel(log_level);
    auto positive = [](const std::string& text, const char* what, double* out) {
      if (text.empty()) return;
      *out = ParseDouble(text, what);
      if (!(*out > 0)) throw std::invalid_argument(std::string(what) + " must be positive");
    };
    positive(publish_rate, "--publish-rate", &options.publish_rate_hz);
    positive(checkpoint_interval, "--checkpoint-interval", &options.checkpoint_interval_s);
    positive(noise_tau, "--noise-tau", &options.estimator.measurement_sigma);
  } catch (const std::invalid_argument& e) {
    std::cerr << "Error: " << e.what() << "\n";
    return 2;
  }

  // The files the daemon writes must not be any of its inputs (nor each other).
  {
    auto same = [](const std::string& a, const std::string& b) {
      if (a.empty() || b.empty()) return false;
      std::error_code ec;
      if (std::filesystem::exists(a, ec) && std::filesystem::exists(b, ec)) return std::filesystem::equivalent(a, b, ec);
      return std::filesystem::weakly_canonical(a, ec) == std::filesystem::weakly_canonical(b, ec);
    };
    const std::pair<const char*, std::string> outputs[] = {{"--checkpoint", options.checkpoint_path},
                                                           {"--write-urdf", write_urdf}};
    const std::pair<const char*, std::string> inputs[] = {
        {"--model", model_path}, {"--config", config_path}, {"--can-config", can_config}};
    for (const auto& [out_option, out] : outputs) {
      for (const auto& [in_option, in] : inputs) {
        if (same(out, in)) {
          std::cerr << "Error: " << out_option << " '" << out << "' is the " << in_option
                    << " input: refusing to overwrite an input\n";
          return 2;
        }
      }
    }
    if (same(options.checkpoint_path, write_urdf)) {
      std::cerr << "Error: --checkpoint and --write-urdf name the same file '" << write_urdf << "'\n";
      return 2;
    }
  }
  std::unique_ptr<EstimationDaemon> daemon;
  RobotModel robot;
  try {
    if (body) {
      Vector10 pi;
      pi << 1, 0, 0, 0, 1, 1, 1, 0, 0, 0;
      if (!prior.empty()) {
        const std::vector<double> v = ParseNumberList(prior, "--prior");
        if (v.size() != 10) throw std::invalid_argument("--prior: " + std::to_string(v.size()) + " numbers, 10 expected");
        pi = Eigen::Map<const Vector10>(v.data());
      }
      daemon = std::make_unique<EstimationDaemon>(InertialParams::FromVector(pi), options);
    } else if (!can_interface.empty()) {
      robot = LoadUrdf(model_path);
      CanConfig can;
      try {
        can = LoadCanConfig(can_config);
      } catch (const std::exception& e) {  // cannot be read, or not a valid motors.yaml: a file error
        std::cerr << "Error: --can-config: " << e.what() << "\n";
        return 5;
      }
      daemon = std::make_unique<EstimationDaemon>(
          MakeRobotDynamics(robot, MergeEffects(robot.DeclaredEffects(), ParseEffectList(effects))), options,
          std::move(can), std::make_unique<SocketCanBus>(can_interface));
    } else {
      robot = LoadUrdf(model_path);
      daemon = std::make_unique<EstimationDaemon>(
          MakeRobotDynamics(robot, MergeEffects(robot.DeclaredEffects(), ParseEffectList(effects))), options);
    }
  } catch (const UrdfError& e) {
    std::cerr << "Error: " << e.what() << "\n";
    return 5;
  } catch (const std::invalid_argument& e) {
    std::cerr << "Error: " << e.what() << "\n";
    return 2;
  } catch (const std::runtime_error& e) {  // LCM or the CAN interface could not start
    std::cerr << "Error: " << e.what() << "\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "Error: " << e.what() << "\n";
    return 2;
  }
  struct sigaction action {};
  action.sa_handler = OnSignal;
  sigemptyset(&action.sa_mask);
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
  if (!write_urdf.empty()) {
    struct sigaction write_action {};
    write_action.sa_handler = OnWriteSignal;
    sigemptyset(&write_action.sa_mask);
    sigaction(SIGUSR1, &write_action, nullptr);
    daemon->set_model_sink(
        [&](const OnlineJointEstimator& estimator) {
          WriteModelUrdf(model_path, write_urdf, robot, estimator.model(), SnapshotWithUncertainty(estimator),
                         "the online estimate of inertiald (" + std::to_string(estimator.estimator().counters().accepted()) +
                             " samples)");
        },
        &g_write_model);
  }
  return daemon->Run(g_stop);
}
