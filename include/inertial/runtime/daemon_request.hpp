/// @file daemon_request.hpp
/// inertiald's request: what its command line asks for (plain values, no command-line library),
/// checked and turned into the daemon's options and a daemon ready to Run (estimation_daemon.hpp).
/// The settings come from the defaults, then the --config file (daemon_config_file.hpp), then the
/// command line's values (daemon_overrides.hpp). Every failure is a DaemonStartError saying which
/// kind it is (inertiald's exit code) and why.
#pragma once

#include <atomic>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "inertial/config/daemon_config.hpp"
#include "inertial/config/daemon_overrides.hpp"
#include "inertial/runtime/estimation_daemon.hpp"

namespace inertial {

struct DaemonRequest {
  std::string model_path;     ///< URDF of a robot (exclusive with body)
  bool body = false;          ///< a single body from inertial.body_wrench_t messages
  std::string prior;          ///< body: its prior pi, 10 numbers (empty: 1 kg, 1 kg m^2 at the origin)
  std::string effects;        ///< robot: effects beyond rigid links (ParseEffectList syntax)
  std::string can_interface;  ///< robot: read motor frames from this SocketCAN interface (with can_config)
  std::string can_config;     ///< motors.yaml of can_interface
  std::string config_path;    ///< the JSON configuration (empty: none)
  std::string write_urdf;     ///< robot: the estimate as a model file at exit and on request (empty: none)
  /// robot: regions given by the user, each --region's text (formats/user_region.hpp), replacing the
  /// automatic ones of the bodies they name.
  std::vector<std::string> regions;
  DaemonOverrides overrides;  ///< the command line's settings over the configuration's
};

/// What kind of failure stopped the start.
enum class StartFailure {
  kUsage,       ///< options that do not go together, or a bad value
  kFileError,   ///< an input file (model, configuration, motors.yaml) unreadable or not valid
  kCannotStart  ///< LCM or the CAN interface could not start
};

/// Why inertiald cannot start: what() the message (without "Error: "), failure() its kind.
class DaemonStartError : public std::runtime_error {
 public:
  DaemonStartError(StartFailure failure, const std::string& message)
      : std::runtime_error(message), failure_(failure) {}
  StartFailure failure() const { return failure_; }

 private:
  StartFailure failure_;
};

/// The options of the request, checked in this order: exactly one of a model and a body; no
/// write_urdf for a body; can_interface and can_config together and only for a robot (kUsage);
/// the configuration file (kFileError); the command line's settings (kUsage); no output
/// (checkpoint, write_urdf) that names an input (model, configuration, motors.yaml) or the other
/// output (kUsage). A body's input channel defaults to INERTIAL_BODY_WRENCH.
/// @throws DaemonStartError.
DaemonOptions DaemonOptionsFor(const DaemonRequest& request);

/// DaemonOptionsFor, then the daemon: the body from its prior, or the robot from its URDF and
/// effects (from LCM, or from the CAN bus of motors.yaml). With write_urdf the daemon writes its
/// estimate as a model file at exit and whenever *write_request is set ("the online estimate of
/// inertiald (N samples)"). @throws DaemonStartError: kFileError for a model or motors.yaml that
/// cannot be used, kUsage for a bad prior or effects, kCannotStart when LCM or the bus fails.
std::unique_ptr<EstimationDaemon> MakeDaemon(const DaemonRequest& request, std::atomic<bool>* write_request);

}  // namespace inertial
