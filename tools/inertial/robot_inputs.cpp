#include "robot_inputs.hpp"

#include <algorithm>
#include <iostream>

#include "exit_codes.hpp"
#include "option_parsing.hpp"
#include "inertial/formats/model_file.hpp"
#include "inertial/formats/number_parsing.hpp"

namespace inertial::cli {

int ParseGravityOption(const std::string& text, Vector3* gravity) {
  try {
    const std::vector<double> g = ParseNumberList(text, "--gravity");
    if (g.size() != 3) {
      std::cerr << "Error: " << NumberCountError("--gravity", 3, g.size(), text) << "\n";
      return kUsage;
    }
    *gravity = Vector3(g[0], g[1], g[2]);
  } catch (const InvalidNumber& e) {
    std::cerr << "Error: " << e.what() << "\n";
    return kInvalidValue;
  }
  return kOk;
}

int LoadRobotModel(const std::string& urdf, RobotModel* robot) {
  try {
    *robot = LoadUrdf(urdf);
  } catch (const UrdfError& e) {
    std::cerr << "Error: " << e.what() << "\n";
    if (std::string(e.what()).find("not physically consistent") != std::string::npos) {
      std::cerr << "hint: `inertial check --model " << urdf << " --repair fixed.urdf` writes the nearest consistent inertias\n";
      return kInconsistentBody;
    }
    return kIoError;
  }
  return kOk;
}

int LoadRobot(const std::string& urdf, const std::string& effects_text, const Vector3& gravity, RobotModel* robot,
              std::vector<EffectSpec>* effects, std::optional<RobotDynamics>* model) {
  try {
    *effects = ParseEffectList(effects_text);
  } catch (const std::invalid_argument& e) {
    std::cerr << "Error: --effects: " << e.what() << "\n";
    return kUsage;
  }
  const int status = LoadRobotModel(urdf, robot);
  if (status != kOk) return status;
  *effects = MergeEffects(robot->DeclaredEffects(), *effects);
  // Bare <dynamics> values (not declared in <inertial_effects>) are not fitted: say so.
  std::string unfitted;
  for (const ModelEffect& m : robot->effects) {
    if (m.spec.text.find("<dynamics>") == std::string::npos) continue;
    const bool covered = std::any_of(effects->begin(), effects->end(), [&](const EffectSpec& e) {
      return e.kind == m.spec.kind && (e.target == m.spec.target || e.target.empty());
    });
    if (!covered) unfitted += (unfitted.empty() ? "" : ", ") + std::string(ToString(m.spec.kind)) + "@" + m.spec.target;
  }
  if (!unfitted.empty()) {
    std::cerr << "note: " << urdf << " states <dynamics> values (" << unfitted
              << ") that are not part of the fitted model; add them with --effects to fit them (validate uses them as "
                 "stated)\n";
  }
  try {
    model->emplace(MakeRobotDynamics(*robot, *effects, gravity));
  } catch (const std::invalid_argument& e) {
    std::cerr << "Error: --effects: " << e.what() << "\n";
    return kUsage;
  }
  return kOk;
}

int ReadRobotLog(const std::string& path, const RobotModel& robot, const JointCsvOptions& csv, JointSamples* samples,
                 std::vector<int>* lines) {
  try {
    JointCsvReport report;
    *samples = ReadJointLog(path, robot.dof_names, csv, &report);
    if (lines != nullptr) *lines = report.lines;
    for (const std::string& n : report.notices) std::cerr << "note: " << n << "\n";
  } catch (const CsvError& e) {
    std::cerr << "Error: " << e.what() << "\n";
    return ExitCodeOf(e);
  }
  return kOk;
}

}  // namespace inertial::cli
