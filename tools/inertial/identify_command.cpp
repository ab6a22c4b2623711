// `inertial identify`: batch identification of a URDF robot from joint logs (eq. 14).
#include <iostream>
#include <map>
#include <optional>
#include <set>

#include "commands.hpp"
#include "exit_codes.hpp"
#include "inertial/io/identification_report.hpp"
#include "inertial/io/joint_csv.hpp"
#include "inertial/io/urdf_writer.hpp"
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
  sub->add_option("--data", c->data, "training log (CSV)")->required();
  sub->add_option("--validate", c->validate, "validation log (CSV): errors of the prior and of the fit on it");
  sub->add_option("--effects", c->effects,
                  "effects beyond rigid links, e.g. viscous,coulomb@knee:scale=0.05,offset,armature,spring,"
                  "payload@tool0:mass=2,rotor@hip:gear=6 (a joint effect without @ applies to every joint)");
  sub->add_option("--prior-weight", c->prior_weight, "gamma of eq. 14, >= 0 (the paper: 1e-2)")->default_val("0.01");
  sub->add_option("--max-iterations", c->max_iterations, "Levenberg-Marquardt iteration cap, 1 to 100000")
      ->default_val("1000");
  sub->add_option("--gravity", c->gravity, "gravity in the base frame, three numbers [m/s^2]")
      ->default_val("0 0 -9.81");
  sub->add_option("--sg-order", c->sg_order, "Savitzky-Golay polynomial order for missing qd/qdd, 2 to 10")
      ->default_val("4");
  sub->add_option("--sg-window", c->sg_window, "Savitzky-Golay window [s] (the paper: 0.1)")->default_val("0.1");
  sub->add_flag("--skip-bad-rows", c->skip_bad_rows, "skip (and count) malformed rows instead of rejecting the file");
  sub->add_option("--predictions", c->predictions,
                  "write t and tau_hat_J for every sample of the validation data (or of the training data)");
  sub->add_option("--write-urdf", c->write_urdf,
                  "write the URDF back with the identified inertias (viscous/coulomb as <dynamics damping friction>)");
  sub->add_flag("--json", c->json, "print the result as JSON on stdout instead of the text report");
  return sub;
}

namespace {

// Writes the identified robot: tree bodies' inertias onto their URDF links (the inertials of links
// merged into them removed), viscous and Coulomb coefficients as <dynamics>. Rotors, payloads and the
// other effects have no URDF form: they are listed on stderr.
void WriteIdentifiedUrdf(const IdentifyCommand& c, const RobotModel& robot, const RobotDynamics& model,
                         const Eigen::VectorXd& x) {
  std::map<std::string, InertialParams> inertias;
  std::set<std::string> removed;
  std::vector<std::string> not_written;
  for (int e = 0; e < static_cast<int>(model.bodies().size()); ++e) {
    const EstimatedBody& body = model.bodies()[e];
    if (body.tree_body < static_cast<int>(robot.body_links.size()) && body.name == robot.body_links[body.tree_body]) {
      inertias[body.name] = model.BodyInertia(e, x);
    } else {
      not_written.push_back(body.name);
    }
  }
  for (const UrdfLinkInertial& link : robot.links) {
    const int b = robot.BodyIndex(link.link);
    if (link.present && b >= 0 && robot.body_links[b] != link.link) removed.insert(link.link);
  }
  std::map<std::string, JointDynamics> dynamics;
  for (int k = 0; k < static_cast<int>(model.effects().size()); ++k) {
    const EffectTerm& t = model.effects()[k];
    if (t.kind == EffectKind::kViscous) {
      dynamics[t.joint].damping = model.EffectValues(k, x)[0];
    } else if (t.kind == EffectKind::kCoulomb) {
      dynamics[t.joint].friction = model.EffectValues(k, x)[0];
    } else {
      not_written.push_back(std::string(ToString(t.kind)) + "@" + t.joint);
    }
  }
  WriteUrdfWithInertias(c.model, c.write_urdf, inertias, removed, dynamics);
  std::cerr << "wrote " << c.write_urdf << ": " << inertias.size() << " link inertias";
  if (!removed.empty()) std::cerr << " (the inertials of " << removed.size() << " merged links moved into them)";
  std::cerr << ", " << dynamics.size() << " joint <dynamics>\n";
  if (!not_written.empty()) {
    std::cerr << "note: URDF cannot hold";
    for (const std::string& n : not_written) std::cerr << " " << n;
    std::cerr << "; they are in the report only\n";
  }
}

}  // namespace

int RunIdentifyCommand(const IdentifyCommand& c) {
  JointIdentificationOptions options;
  JointCsvOptions csv;
  csv.skip_bad_rows = c.skip_bad_rows;
  int status = ParseRealOption(c.prior_weight, "--prior-weight", 0.0, 1e12, &options.prior_weight);
  if (status == kOk) status = ParseInteger(c.max_iterations, "--max-iterations", 1, 100000, &options.lm.max_iterations);
  if (status == kOk) status = ParseInteger(c.sg_order, "--sg-order", 2, 10, &csv.differentiation.order);
  if (status == kOk) status = ParseRealOption(c.sg_window, "--sg-window", 1e-6, 1e6, &csv.differentiation.window);
  if (status != kOk) return status;
  Vector3 gravity;
  status = ParseGravityOption(c.gravity, &gravity);
  if (status != kOk) return status;
  RobotModel robot;
  std::vector<EffectSpec> effects;
  std::optional<RobotDynamics> model;
  status = LoadRobot(c.model, c.effects, gravity, &robot, &effects, &model);
  if (status != kOk) return status;
  JointSamples train, validation;
  status = ReadRobotLog(c.data, robot, csv, &train);
  if (status == kOk && !c.validate.empty()) status = ReadRobotLog(c.validate, robot, csv, &validation);
  if (status != kOk) return status;
  if (train.size() < 2) {
    std::cerr << "Error: " << c.data << ": " << train.size() << " samples; identification needs more\n";
    return kInvalidValue;
  }

  const IdentificationRun run =
      RunIdentification(*model, train, c.validate.empty() ? nullptr : &validation, options);
  if (c.json) {
    std::cout << IdentificationJson(*model, run).dump(2) << "\n";
  } else {
    std::cout << IdentificationText(*model, run);
  }
  try {
    if (!c.predictions.empty()) {
      const JointSamples& data = c.validate.empty() ? train : validation;
      const Eigen::MatrixXd tau = PredictJointTorques(*model, run.fit.x, data);
      Eigen::MatrixXd columns(data.size(), 1 + model->num_dofs());
      columns << data.t, tau;
      std::vector<std::string> header{"t"};
      for (const std::string& j : model->dof_names()) header.push_back("tau_hat_" + j);
      WriteColumnsCsv(c.predictions, header, columns);
    }
    if (!c.write_urdf.empty()) WriteIdentifiedUrdf(c, robot, *model, run.fit.x);
  } catch (const CsvError& e) {
    std::cerr << "Error: " << e.what() << "\n";
    return kIoError;
  } catch (const UrdfError& e) {
    std::cerr << "Error: " << e.what() << "\n";
    return kIoError;
  }
  if (!run.fit.lm.converged()) {
    std::cerr << "warning: the fit stopped on " << ToString(run.fit.lm.reason) << " after " << run.fit.lm.iterations
              << " iterations without converging (raise --max-iterations or --prior-weight)\n";
  }
  return kOk;
}

}  // namespace inertial::cli
