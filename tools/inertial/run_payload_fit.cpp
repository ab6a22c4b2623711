#include "run_payload_fit.hpp"

#include <algorithm>
#include <iostream>
#include <optional>

#include "exit_codes.hpp"
#include "inertial/estimation/batch/run_local_bodies.hpp"
#include "inertial/model/number_text.hpp"
#include "inertial/signal/sample_selection.hpp"

namespace inertial::cli {
namespace {

// Which bodies and parameters the fit holds: the links (validate, --hold-links) and the effects at
// their stated values (validate), and the alpha of each payload whose mass is stated (m = e^{2
// alpha} m_prior, joint_identification.hpp).
JointIdentificationOptions HeldParts(const RobotDynamics& model, const RunPayloadFit& fit,
                                     const std::vector<const RunPayload*>& fitted) {
  JointIdentificationOptions options = fit.options;
  const int B = static_cast<int>(model.bodies().size()), first = B - static_cast<int>(fitted.size());
  options.frozen_bodies.assign(static_cast<size_t>(B), false);
  for (int e = 0; e < first; ++e) {
    const bool payload = model.bodies()[static_cast<size_t>(e)].name.rfind("payload@", 0) == 0;
    options.frozen_bodies[static_cast<size_t>(e)] = fit.stated_effects.has_value() || (fit.hold_links && !payload);
  }
  for (size_t u = 0; u < fitted.size(); ++u) {
    if (fitted[u]->mass_known) options.held_parameters.push_back(10 * (first + static_cast<int>(u)));
  }
  if (fit.stated_effects) {
    options.initial = model.ParametersFromEffectValues(*fit.stated_effects);
    for (const EffectTerm& t : model.effects()) {
      for (int k = 0; k < t.size(); ++k) options.held_parameters.push_back(t.first_parameter + k);
    }
  }
  return options;
}

// The fit of x on each run but its held-out share; throws std::invalid_argument.
DenseLevenbergMarquardtResult FitRuns(const RobotDynamics& model, const std::vector<JointSamples>& logs,
                                      const std::vector<Eigen::MatrixXd>& known, const std::vector<int>& body_runs,
                                      double holdout, const std::vector<int>& gain_dofs,
                                      const JointIdentificationOptions& options) {
  std::vector<JointSamples> runs;
  std::vector<Eigen::MatrixXd> knowns;
  for (size_t k = 0; k < logs.size(); ++k) {
    const int rows = holdout > 0.0 ? HoldoutStart(logs[k].t, holdout) : logs[k].size();
    runs.push_back(SelectSamples(logs[k], RowRange(0, rows)));
    knowns.push_back(known[k].topRows(rows));
  }
  if (gain_dofs.empty()) {
    for (size_t k = 0; k < runs.size(); ++k) runs[k].tau -= knowns[k];
    return IdentifyJointModel(model, AccumulateRunNormalEquations(model, runs, body_runs), options).lm;
  }
  Eigen::Index rows = 0;
  for (const Eigen::MatrixXd& m : knowns) rows += m.rows();
  Eigen::MatrixXd all(rows, model.num_dofs());
  rows = 0;
  for (const Eigen::MatrixXd& m : knowns) {
    all.middleRows(rows, m.rows()) = m;
    rows += m.rows();
  }
  if (const std::optional<std::string> why =
          GainScaleProblem(model, all, gain_dofs, options.frozen_bodies, options.held_parameters)) {
    throw std::domain_error(*why);
  }
  return IdentifyWithGains(model, AccumulateRunGainProblem(model, runs, knowns, gain_dofs, body_runs), options).fit.lm;
}

void PrintFitted(const RunPayload& p) {
  const Vector3 c = p.body.com();
  const Matrix3 I = p.body.rotational_inertia_about_com();
  std::cerr << "note: " << p.file << ": the payload on " << p.link << " fitted with the model from every run: mass "
            << FormatNumber(p.body.mass(), 6) << " kg" << (p.mass_known ? " (as stated)" : "") << ", COM "
            << FormatNumber(c.x(), 4) << ", " << FormatNumber(c.y(), 4) << ", " << FormatNumber(c.z(), 4)
            << " m, inertia about the COM (Ixx Iyy Izz Ixy Ixz Iyz) " << FormatNumber(I(0, 0), 3) << " "
            << FormatNumber(I(1, 1), 3) << " " << FormatNumber(I(2, 2), 3) << " " << FormatNumber(I(0, 1), 3) << " "
            << FormatNumber(I(0, 2), 3) << " " << FormatNumber(I(1, 2), 3) << " kg m^2 (in " << p.link
            << "'s frame); its torques are taken out of this run's\n";
}

// Why a payload to be fitted cannot be told from its link, or nullopt: with the links fitted, a
// link whose every run carries a payload to be fitted on it (or that carries two in one run) leaves
// the split between link and payload to the regularizer.
std::optional<std::string> Inseparable(const RobotDynamics& model, int first, const std::vector<int>& body_runs,
                                       int num_runs, bool links_held) {
  const int B = static_cast<int>(model.bodies().size());
  for (int e = first; e < B; ++e) {
    const int tree = model.bodies()[static_cast<size_t>(e)].tree_body;
    std::vector<int> carried(static_cast<size_t>(num_runs), 0);
    for (int f = first; f < B; ++f) {
      if (model.bodies()[static_cast<size_t>(f)].tree_body == tree) ++carried[static_cast<size_t>(body_runs[static_cast<size_t>(f)])];
    }
    const std::string link = model.bodies()[static_cast<size_t>(e)].name.substr(8);  // after "payload@"
    if (carried[static_cast<size_t>(body_runs[static_cast<size_t>(e)])] > 1) {
      return "two payloads to be fitted move with " + link + " in one run: give them as one";
    }
    if (!links_held && std::count(carried.begin(), carried.end(), 0) == 0) {
      return "every run carries a payload to be fitted that moves with " + link +
             ", so nothing tells the payload from the link: add a run without it, or state its com=";
    }
  }
  return std::nullopt;
}

}  // namespace

int FitRunPayloads(const std::vector<std::string>& files, const std::vector<JointSamples>& logs,
                   const std::vector<Eigen::MatrixXd>& known, const RobotModel& robot, const Vector3& gravity,
                   const RunPayloadFit& fit, const std::vector<int>& gain_dofs, std::vector<RunPayload>* payloads) {
  std::vector<EffectSpec> specs = fit.effects;
  std::vector<RunPayload*> fitted;
  for (RunPayload& p : *payloads) {
    if (p.known) continue;
    EffectSpec e = ParseEffectList("payload@" + p.link)[0];
    e.inertia = p.body;  // the prior: the stated mass (or 0.5 kg) at the link's origin
    e.own_features = true;
    e.text = "--run-payload " + p.text;
    specs.push_back(e);
    fitted.push_back(&p);
  }
  if (fitted.empty()) return kOk;
  std::optional<RobotDynamics> model;
  try {
    model.emplace(MakeRobotDynamics(robot, specs, gravity));
  } catch (const std::invalid_argument& e) {  // a link the robot lacks, or one fixed to the base
    std::cerr << "Error: " << e.what() << "\n";
    return kUsage;
  }
  if (const int status = ApplyRegionOptions(robot, fit.regions, &*model, false); status != kOk) return status;
  const int first = static_cast<int>(model->bodies().size() - fitted.size());
  std::vector<int> body_runs(model->bodies().size(), -1);
  for (size_t u = 0; u < fitted.size(); ++u) {
    body_runs[static_cast<size_t>(first) + u] =
        static_cast<int>(std::find(files.begin(), files.end(), fitted[u]->file) - files.begin());
  }
  const bool links_held = fit.stated_effects.has_value() || fit.hold_links;
  if (const std::optional<std::string> why =
          Inseparable(*model, first, body_runs, static_cast<int>(files.size()), links_held)) {
    std::cerr << "Error: --run-payload: " << *why << "\n";
    return kUsage;
  }
  try {
    const std::vector<const RunPayload*> view(fitted.begin(), fitted.end());
    const JointIdentificationOptions options = HeldParts(*model, fit, view);
    const DenseLevenbergMarquardtResult lm = FitRuns(*model, logs, known, body_runs, fit.holdout, gain_dofs, options);
    if (!lm.converged()) {
      std::cerr << "warning: the fit of the run payloads stopped on " << ToString(lm.reason) << " after "
                << lm.iterations << " iterations without converging (raise --max-iterations)\n";
    }
    for (size_t u = 0; u < fitted.size(); ++u) {
      fitted[u]->body = model->BodyInertia(first + static_cast<int>(u), lm.x);
      fitted[u]->known = true;
      PrintFitted(*fitted[u]);
    }
  } catch (const std::domain_error& e) {
    std::cerr << "Error: gain@: " << e.what() << "\n";
    return kUsage;
  } catch (const std::invalid_argument& e) {
    std::cerr << "Error: fitting the run payloads: " << e.what() << "\n";
    return kInvalidValue;
  }
  if (links_held) {
    std::cerr << "note: the payloads' COM and inertia were fitted to their runs with the model held, so those runs' "
                 "errors judge the model less strictly than the others' (state com= to judge them alike)\n";
  }
  return kOk;
}

}  // namespace inertial::cli
