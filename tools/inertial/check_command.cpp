// `inertial check`: physical consistency of every link of a URDF, and repair (link_inertial_check.hpp).
#include <iostream>
#include <optional>

#include "commands.hpp"
#include "exit_codes.hpp"
#include "option_parsing.hpp"
#include "robot_inputs.hpp"
#include "inertial/formats/link_inertial_check.hpp"
#include "inertial/formats/model_file.hpp"
#include "inertial/formats/model_plausibility.hpp"
#include "inertial/report/link_inertial_report.hpp"
#include "inertial/report/plausibility_report.hpp"

namespace inertial::cli {

CLI::App* AddCheckCommand(CLI::App& app, CheckCommand* c) {
  CLI::App* sub = app.add_subcommand(
      "check",
      "Check every link's <inertial> of a URDF for full physical consistency (mass > 0, inertia at the COM "
      "positive definite, triangle inequalities of the principal moments, pseudo-inertia positive definite), "
      "with margins, and each moving body's plausibility (against the priors a model file records, else against its "
      "collision shapes or, without them, its density over its segment region; as identify judges its fit). Exit 0 "
      "if every link is consistent, 4 if any is not (also with --repair, which fixes the written copy, not the file "
      "checked); an implausible body is reported, not an exit code.");
  sub->add_option("--model", c->model, "URDF robot description")->required();
  sub->add_option("--repair", c->repair,
                  "write a copy whose impossible links get the nearest consistent inertia: same mass and COM, "
                  "the second moments about the COM clipped from below (the Frobenius-nearest pseudo-inertia at "
                  "the COM), never thinner than 1 mm of spread or 1e-3 of the largest second moment");
  sub->add_option("--total-mass", c->total_mass,
                  "the whole robot as weighed; the links plus the links fixed to the base are judged against it");
  sub->add_flag("--json", c->json, "print the report as JSON on stdout");
  return sub;
}

namespace {

// The bodies' plausibility (formats/model_plausibility.hpp) and, with a bound, the links' total, as
// text and JSON fields; a URDF that does not load as a model (an impossible link) is not judged.
void JudgePlausibility(const std::string& path, const std::optional<double>& total_mass, std::string* text,
                       nlohmann::json* json) {
  RobotModel robot;
  std::optional<RobotDynamics> model;
  try {
    robot = LoadUrdf(path);
    PrintUnreadMeshesNote(robot, path);
    model.emplace(MakeRobotDynamics(robot, robot.DeclaredEffects()));
  } catch (const std::exception& e) {
    *text = "Plausibility: not judged (the file does not load as a model: " + std::string(e.what()) + ")\n";
    (*json)["plausibility"] = nullptr;
    (*json)["plausible"] = nullptr;
    return;
  }
  const Eigen::VectorXd x = Eigen::VectorXd::Zero(model->num_parameters());  // every body as the file states it
  const std::vector<JudgedBody> judged = JudgeModelBodies(robot, *model, x);
  *text = ModelPlausibilityText(judged);
  const nlohmann::json bodies = ModelPlausibilityJson(judged);
  (*json)["plausibility"] = bodies["bodies"];
  bool plausible = bodies["plausible"].get<bool>();
  if (total_mass) {
    const TotalMassPlausibility t = JudgeTotalMass(*model, x, TotalMassBound{*total_mass, MassFixedToBase(robot)});
    *text += TotalMassText(t) + TotalMassWarning(t);
    (*json)["total_mass"] = TotalMassJson(t);
    plausible = plausible && t.within;
  }
  (*json)["plausible"] = plausible;
}

}  // namespace

int RunCheckCommand(const CheckCommand& c) {
  if (const int status = RefuseOverwritingInputs({{"--repair", c.repair}}, {{"--model", c.model}}); status != kOk) {
    return status;
  }
  std::optional<double> total_mass;
  if (!c.total_mass.empty()) {
    total_mass.emplace();
    if (const int status = ParseRealOption(c.total_mass, "--total-mass", 1e-9, 1e6, &*total_mass); status != kOk) {
      return status;
    }
  }
  UrdfInertialCheck check;
  std::optional<UrdfRepair> repair;
  try {
    check = CheckUrdfInertials(c.model);
    if (!c.repair.empty()) repair = WriteRepairedUrdf(check, c.repair);
  } catch (const UrdfError& e) {
    std::cerr << "Error: " << e.what() << "\n";
    return kIoError;
  }
  const UrdfRepair* written = repair ? &*repair : nullptr;
  std::string plausibility;
  nlohmann::json plausibility_json = nlohmann::json::object();
  JudgePlausibility(c.model, total_mass, &plausibility, &plausibility_json);
  if (c.json) {
    nlohmann::json j = LinkInertialJson(check, written);
    j.update(plausibility_json);
    std::cout << j.dump(2) << "\n";
  } else {
    std::cout << LinkInertialText(check, written) << (plausibility.empty() ? "" : "\n" + plausibility);
  }
  return check.impossible() == 0 ? kOk : kInconsistentBody;
}

}  // namespace inertial::cli
