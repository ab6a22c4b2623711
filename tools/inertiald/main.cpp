// inertiald: the online estimator beside the controller. Reads joint-state messages from LCM,
// updates the log-Cholesky estimate every sample, publishes inertial.estimate_t at a fixed rate,
// checkpoints its state, and stops cleanly on SIGINT or SIGTERM (estimation_daemon.hpp). This file
// only reads the command line into a DaemonRequest (daemon_request.hpp) and handles the signals.
#include <CLI/CLI.hpp>
#include <csignal>
#include <iostream>
#include <optional>

#include "command_line.hpp"
#include "numeric_options.hpp"
#include "inertial/runtime/daemon_request.hpp"

namespace {

std::atomic<bool> g_stop{false};
std::atomic<bool> g_write_model{false};

extern "C" void OnSignal(int) { g_stop = true; }
extern "C" void OnWriteSignal(int) { g_write_model = true; }

// inertiald's options, in the order --help lists them.
void AddDaemonOptions(CLI::App& app, inertial::DaemonRequest* r) {
  inertial::DaemonOverrides& o = r->overrides;
  app.add_option("--model", r->model_path, "URDF robot description (robots)");
  app.add_flag("--body", r->body,
               "a single body on a wrench sensor: inertial.body_wrench_t messages (default channel INERTIAL_BODY_WRENCH)");
  app.add_option("--prior", r->prior, "--body: the prior body's pi (default 1 kg, 1 kg m^2 at the origin)");
  app.add_option("--can", r->can_interface, "read the motors' frames from this SocketCAN interface (e.g. can0) instead of LCM");
  app.add_option("--can-config", r->can_config, "motors.yaml for --can: which frames are which joint's, and how to decode them");
  app.add_option("--effects", r->effects, "effects beyond rigid links (syntax of `inertial identify --effects`)");
  app.add_option("--region", r->regions,
                 "LINK=cx,cy,cz,a,b,c[:rpy=r,p,y]: the region LINK's mass may occupy, replacing the automatic one "
                 "(syntax of `inertial identify --region`; payload@LINK for a payload); once per link");
  app.add_option("--config", r->config_path, "JSON configuration (channels, rates, checkpoint, message format)");
  app.add_option("--lcm-url", o.lcm_url, "LCM provider URL (default LCM's: udpm://239.255.76.67:7667)");
  app.add_option("--channel", o.channel, "joint-state channel (default INERTIAL_JOINT_STATE)");
  app.add_option("--estimate-channel", o.estimate_channel, "estimate channel (default INERTIAL_ESTIMATE)");
  app.add_option("--residual-channel", o.residual_channel, "publish inertial.residual_t per sample on this channel");
  app.add_option("--checkpoint", o.checkpoint, "estimator state file: restored at start, saved periodically and at exit");
  app.add_option("--checkpoint-interval", o.checkpoint_interval, "seconds between checkpoints (default 5)");
  app.add_flag("--fresh", o.fresh,
               "start from the priors even if --checkpoint names a file that cannot be restored (it is then "
               "overwritten); without it such a file stops the start and is left untouched");
  app.add_option("--publish-rate", o.publish_rate, "estimates per second (default 10)");
  app.add_option("--estimator", o.estimator, "gauss_newton (default: the online fit, the batch objective re-solved from its statistics on a thread of its own), ekf, gradient or linear_rls");
  app.add_option("--noise-tau", o.noise_tau, "torque noise standard deviation the estimator assumes [N m] (default 1)");
  app.add_option("--write-urdf", r->write_urdf,
                 "write the current estimate as a model file (URDF: links, effects, rotors, payloads) at exit and on "
                 "SIGUSR1, for `inertial validate --model` or as the next prior");
  app.add_option("--log-level", o.log_level, "error, warn, info (default) or debug");
}

// SIGINT and SIGTERM stop the daemon; with --write-urdf, SIGUSR1 asks for the model file.
void InstallSignalHandlers(bool write_model) {
  struct sigaction action {};
  action.sa_handler = OnSignal;
  sigemptyset(&action.sa_mask);
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
  if (!write_model) return;
  struct sigaction write_action {};
  write_action.sa_handler = OnWriteSignal;
  sigemptyset(&write_action.sa_mask);
  sigaction(SIGUSR1, &write_action, nullptr);
}

// The exit codes of --help: 1 LCM (or CAN) failure, 2 usage, 5 a file error.
int ExitCodeOf(inertial::StartFailure failure) {
  switch (failure) {
    case inertial::StartFailure::kCannotStart: return 1;
    case inertial::StartFailure::kFileError: return 5;
    case inertial::StartFailure::kUsage: break;
  }
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "inertiald: online, physically consistent inertia estimation beside the controller. Subscribes to joint-state "
      "messages on LCM (inertial.joint_state_t, or the user's own type described in --config), runs the recursive "
      "estimator on every sample and publishes inertial.estimate_t. Exit codes: 0 ok, 1 LCM failure, 2 usage, "
      "5 a file error (model, config, motors.yaml, checkpoint: unreadable, too large or not valid)."};
  inertial::DaemonRequest request;
  AddDaemonOptions(app, &request);
  app.name("inertiald");
  app.set_version_flag("--version", "inertiald " INERTIAL_VERSION);
  inertial::cli::DescribeNumericOptions(app);
  if (const std::optional<int> done = inertial::cli::ParseCommandLine(app, argc, argv, 2)) return *done;

  std::unique_ptr<inertial::EstimationDaemon> daemon;
  try {
    daemon = inertial::MakeDaemon(request, &g_write_model);
  } catch (const inertial::DaemonStartError& e) {
    std::cerr << "Error: " << e.what() << "\n";
    return ExitCodeOf(e.failure());
  }
  InstallSignalHandlers(!request.write_urdf.empty());
  return daemon->Run(g_stop);
}
