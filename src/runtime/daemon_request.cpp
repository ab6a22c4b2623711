#include "inertial/runtime/daemon_request.hpp"

#include <filesystem>
#include <utility>

#include "inertial/config/daemon_config_file.hpp"
#include "inertial/config/motors_yaml.hpp"
#include "inertial/formats/estimator_state_file.hpp"
#include "inertial/formats/model_file.hpp"
#include "inertial/formats/number_parsing.hpp"
#include "inertial/formats/output_paths.hpp"
#include "inertial/formats/user_region.hpp"
#include "inertial/report/uncertainty_report.hpp"
#include "inertial/transport/can_bus.hpp"

namespace inertial {

namespace {

[[noreturn]] void Fail(StartFailure failure, const std::string& message) { throw DaemonStartError(failure, message); }

// The options that must or must not go together.
void CheckCombination(const DaemonRequest& r) {
  if (r.body == !r.model_path.empty()) {
    Fail(StartFailure::kUsage, std::string("give --model URDF (a robot) or --body (a single body), not ") +
                                   (r.body ? "both" : "neither"));
  }
  if (r.body && !r.write_urdf.empty()) {
    Fail(StartFailure::kUsage, "--write-urdf needs --model (a single body has no URDF; its estimate is in estimate_t)");
  }
  if (r.can_interface.empty() != r.can_config.empty() || (r.body && !r.can_interface.empty())) {
    Fail(StartFailure::kUsage, "--can and --can-config go together, with --model");
  }
}

void ApplyConfigFile(const std::string& path, DaemonOptions* options) {
  try {
    ApplyDaemonConfigFile(path, options);
  } catch (const DaemonConfigFileError& e) {
    switch (e.reason()) {
      case DaemonConfigFileError::Reason::kUnreadable:
      case DaemonConfigFileError::Reason::kTooLarge: Fail(StartFailure::kFileError, std::string("--config: ") + e.what());
      case DaemonConfigFileError::Reason::kNotJson:
        Fail(StartFailure::kFileError, "--config: " + path + " is not valid JSON: " + e.what());
      case DaemonConfigFileError::Reason::kInvalid: Fail(StartFailure::kFileError, "--config " + path + ": " + e.what());
    }
  }
}

// The files the daemon writes must not be any of its inputs (nor each other).
void CheckOutputs(const DaemonRequest& r, const DaemonOptions& options) {
  if (const std::optional<std::string> clash =
          OutputPathClash({{"--checkpoint", options.checkpoint_path}, {"--write-urdf", r.write_urdf}},
                          {{"--model", r.model_path}, {"--config", r.config_path}, {"--can-config", r.can_config}})) {
    Fail(StartFailure::kUsage, *clash);
  }
}

// --prior's 10 numbers, or 1 kg with unit inertia at the origin.
InertialParams BodyPrior(const std::string& text) {
  Vector10 pi;
  pi << 1, 0, 0, 0, 1, 1, 1, 0, 0, 0;
  if (!text.empty()) {
    const std::vector<double> v = ParseNumberList(text, "--prior");
    if (v.size() != 10) {
      throw std::invalid_argument("--prior: " + std::to_string(v.size()) + " numbers given, 10 expected ('" + text + "')");
    }
    pi = Eigen::Map<const Vector10>(v.data());
  }
  return InertialParams::FromVector(pi);
}

// The model sink of --write-urdf: the estimate as a model file (the robot is shared by the sink's copies).
void WriteModelOnRequest(const DaemonRequest& r, RobotModel robot, EstimationDaemon* daemon,
                         std::atomic<bool>* request) {
  auto shared = std::make_shared<const RobotModel>(std::move(robot));
  daemon->set_model_sink(
      [shared, model_path = r.model_path, out = r.write_urdf](const OnlineJointEstimator& estimator) {
        // Under the estimator's lock: the snapshot. After it (the writer thread): the file.
        ModelSnapshot snapshot = SnapshotWithUncertainty(estimator);
        snapshot.measurement = MeasurementEffects(shared->effects);  // the gains it read the log with
        std::string description = "the online estimate of inertiald (" +
                                  std::to_string(estimator.estimator().counters().accepted()) + " samples)";
        const RobotDynamics* dynamics = &estimator.model();  // fixed for the daemon's life
        return std::function<void()>(
            [shared, model_path, out, dynamics, snapshot = std::move(snapshot), description = std::move(description)] {
              WriteModelUrdf(model_path, out, *shared, *dynamics, snapshot, description);
            });
      },
      request);
}

// motors.yaml: one that cannot be read or is not valid is a file error.
CanConfig LoadMotors(const std::string& path) {
  try {
    return LoadCanConfig(path);
  } catch (const std::exception& e) {
    Fail(StartFailure::kFileError, std::string("--can-config: ") + e.what());
  }
}

// In the order inertiald always had: the URDF, motors.yaml, the bus, then the effects and the model.
std::unique_ptr<EstimationDaemon> MakeRobotDaemon(const DaemonRequest& r, DaemonOptions options,
                                                  std::atomic<bool>* write_request) {
  RobotModel robot = LoadUrdf(r.model_path);
  options.log_gains = StatedLogGains(robot, robot.effects);  // a log of currents, in N m first
  std::vector<UserRegion> regions;
  for (const std::string& text : r.regions) {
    try {
      regions.push_back(ParseUserRegion(text));
    } catch (const std::invalid_argument& e) {  // InvalidNumber names the option itself
      Fail(StartFailure::kUsage, dynamic_cast<const InvalidNumber*>(&e) != nullptr ? e.what()
                                                                                   : "--region " + text + ": " + e.what());
    }
  }
  auto model = [&] {
    RobotDynamics m = MakeRobotDynamics(robot, MergeEffects(robot.DeclaredEffects(), ParseEffectList(r.effects)));
    try {
      ApplyUserRegions(robot, regions, &m);
    } catch (const std::invalid_argument& e) {
      Fail(StartFailure::kUsage, std::string("--region ") + e.what());
    }
    return m;
  };
  std::unique_ptr<EstimationDaemon> daemon;
  if (r.can_interface.empty()) {
    daemon = std::make_unique<EstimationDaemon>(model(), std::move(options));
  } else {
    CanConfig can = LoadMotors(r.can_config);
    auto bus = std::make_unique<SocketCanBus>(r.can_interface);
    daemon = std::make_unique<EstimationDaemon>(model(), std::move(options), std::move(can), std::move(bus));
  }
  if (!r.write_urdf.empty()) WriteModelOnRequest(r, std::move(robot), daemon.get(), write_request);
  return daemon;
}

}  // namespace

DaemonOptions DaemonOptionsFor(const DaemonRequest& r) {
  CheckCombination(r);
  DaemonOptions options;
  if (r.body) options.input_channel = "INERTIAL_BODY_WRENCH";
  if (!r.config_path.empty()) ApplyConfigFile(r.config_path, &options);
  try {
    ApplyDaemonOverrides(r.overrides, &options);
  } catch (const std::invalid_argument& e) {
    Fail(StartFailure::kUsage, e.what());
  }
  CheckOutputs(r, options);
  return options;
}

std::unique_ptr<EstimationDaemon> MakeDaemon(const DaemonRequest& r, std::atomic<bool>* write_request) {
  DaemonOptions options = DaemonOptionsFor(r);
  try {
    if (r.body) return std::make_unique<EstimationDaemon>(BodyPrior(r.prior), std::move(options));
    return MakeRobotDaemon(r, std::move(options), write_request);
  } catch (const DaemonStartError&) {
    throw;
  } catch (const UrdfError& e) {
    Fail(StartFailure::kFileError, e.what());
  } catch (const StateFileError& e) {  // --checkpoint names a file that cannot be restored
    Fail(StartFailure::kFileError, e.what());
  } catch (const std::invalid_argument& e) {
    Fail(StartFailure::kUsage, e.what());
  } catch (const std::runtime_error& e) {  // LCM or the CAN interface could not start
    Fail(StartFailure::kCannotStart, e.what());
  } catch (const std::exception& e) {
    Fail(StartFailure::kUsage, e.what());
  }
}

}  // namespace inertial
