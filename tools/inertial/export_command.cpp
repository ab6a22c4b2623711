// `inertial export`: an inertiald checkpoint (estimator state file) as a model file (URDF).
#include <iostream>

#include "commands.hpp"
#include "exit_codes.hpp"
#include "inertial/runtime/estimation_daemon.hpp"
#include "inertial/formats/estimator_state_file.hpp"
#include "inertial/formats/model_file.hpp"
#include "inertial/report/uncertainty_report.hpp"
#include "option_parsing.hpp"
#include "robot_inputs.hpp"

namespace inertial::cli {

CLI::App* AddExportCommand(CLI::App& app, ExportCommand* c) {
  CLI::App* sub = app.add_subcommand(
      "export",
      "Write the model an inertiald checkpoint holds as a model file (URDF: links, effects, rotors, payloads), for "
      "validate --model or as the next prior. Give the --model and --effects the daemon ran with.");
  sub->add_option("--model", c->model, "the URDF inertiald was started with")->required();
  sub->add_option("--effects", c->effects, "the --effects inertiald was started with");
  sub->add_option("--checkpoint", c->checkpoint, "inertiald's checkpoint (estimator state file)")->required();
  sub->add_option("--write-urdf", c->write_urdf, "the model file to write")->required();
  return sub;
}

int RunExportCommand(const ExportCommand& c) {
  int status = RefuseOverwritingInputs({{"--write-urdf", c.write_urdf}},
                                       {{"--model", c.model}, {"--checkpoint", c.checkpoint}});
  if (status != kOk) return status;
  RobotModel robot;
  std::vector<EffectSpec> effects;
  std::optional<RobotDynamics> model;
  status = LoadRobot(c.model, c.effects, Vector3(0, 0, -9.81), &robot, &effects, &model);
  if (status != kOk) return status;
  EstimatorState state;
  std::string description;
  try {
    state = LoadEstimatorState(c.checkpoint, &description);
  } catch (const StateFileError& e) {
    std::cerr << "Error: " << e.what() << "\n";
    return kIoError;
  }
  OnlineEstimatorOptions options;
  try {
    options.kind = ParseEstimatorKind(state.kind);
  } catch (const std::invalid_argument& e) {
    std::cerr << "Error: " << c.checkpoint << ": " << e.what() << "\n";
    return kIoError;
  }
  OnlineJointEstimator estimator(*model, Eigen::VectorXd::Zero(model->num_parameters()), options);
  if (description != CheckpointDescription(estimator)) {
    std::cerr << "Error: " << c.checkpoint << " is of another model (" << description
              << "); give the --model and --effects inertiald ran with\n";
    return kUsage;
  }
  std::string why;
  if (!estimator.Restore(state, &why)) {
    std::cerr << "Error: " << c.checkpoint << ": cannot be restored: " << why << "\n";
    return kIoError;
  }
  try {
    WriteModelUrdf(c.model, c.write_urdf, robot, *model, SnapshotWithUncertainty(estimator),
                   "the online estimate in " + c.checkpoint + " (" + std::to_string(state.counters.accepted()) +
                       " samples)");
  } catch (const std::invalid_argument& e) {
    std::cerr << "Error: " << c.checkpoint << ": " << e.what() << "\n";
    return kInconsistentBody;
  } catch (const UrdfError& e) {
    std::cerr << "Error: " << e.what() << "\n";
    return kIoError;
  }
  std::cerr << "wrote " << c.write_urdf << ": the model of " << c.checkpoint << "\n";
  return kOk;
}

}  // namespace inertial::cli
