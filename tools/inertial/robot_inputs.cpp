#include "robot_inputs.hpp"

#include "run_payload_fit.hpp"

#include <algorithm>
#include <iostream>

#include "exit_codes.hpp"
#include "option_parsing.hpp"
#include "inertial/formats/model_file.hpp"
#include "inertial/formats/model_plausibility.hpp"
#include "inertial/formats/number_parsing.hpp"
#include "inertial/inertia/closed_form_bodies.hpp"
#include "inertial/inertia/consistency.hpp"
#include "inertial/model/body_torques.hpp"
#include "inertial/model/number_text.hpp"

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

void PrintUnreadMeshesNote(const RobotModel& robot, const std::string& urdf) {
  // Meshes that could have drawn a link's region: the link falls back on its segment (body_region.hpp).
  if (robot.unread_meshes.empty()) return;
  std::cerr << "note: " << robot.unread_meshes.size() << " mesh" << (robot.unread_meshes.size() == 1 ? "" : "es")
            << " of " << urdf << " not read, so the bodies they draw get their regions from their joints and priors: "
            << robot.unread_meshes.front();
  for (std::size_t i = 1; i < std::min<std::size_t>(robot.unread_meshes.size(), 3); ++i) std::cerr << "; " << robot.unread_meshes[i];
  if (robot.unread_meshes.size() > 3) std::cerr << "; and " << robot.unread_meshes.size() - 3 << " more";
  std::cerr << " (package:// is looked for in $ROS_PACKAGE_PATH, $AMENT_PREFIX_PATH/share and above the URDF)\n";
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
  PrintUnreadMeshesNote(*robot, urdf);
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

int ParseRegionOptions(const std::vector<std::string>& items, std::vector<UserRegion>* regions) {
  for (const std::string& item : items) {
    try {
      regions->push_back(ParseUserRegion(item));
    } catch (const InvalidNumber& e) {
      std::cerr << "Error: " << e.what() << "\n";
      return kInvalidValue;
    } catch (const std::invalid_argument& e) {
      std::cerr << "Error: --region " << item << ": " << e.what() << "\n";
      return kUsage;
    }
  }
  return kOk;
}

int ApplyRegionOptions(const RobotModel& robot, const std::vector<UserRegion>& regions, RobotDynamics* model,
                       bool require_body) {
  try {
    ApplyUserRegions(robot, regions, model, require_body);
  } catch (const std::invalid_argument& e) {
    std::cerr << "Error: --region " << e.what() << "\n";
    return kUsage;
  }
  return kOk;
}

int ParseTotalMassOption(const std::string& text, const RobotModel& robot, const RobotDynamics& model, bool held_links,
                         std::optional<TotalMassBound>* bound) {
  if (text.empty()) return kOk;
  double total = 0.0;
  // Up to 1e6 kg: beyond the heaviest machines a URDF describes (a robot weighed in grams is caught).
  const int status = ParseRealOption(text, "--total-mass", 1e-9, 1e6, &total);
  if (status != kOk) return status;
  const double fixed = MassFixedToBase(robot);
  const double links = LinkMassSum(model, Eigen::VectorXd::Zero(model.num_parameters()));
  const double held = fixed + (held_links ? links : 0.0);
  // The fit needs room under the bound for what it may move (total_mass_barrier.hpp, IntoTotalMassBound).
  if (!(held < (1.0 - kTotalMassOnset) * total)) {
    std::cerr << "Error: --total-mass " << text << ": the " << (held_links ? "links held at the URDF and those " : "links ")
              << "fixed to the base already weigh " << FormatNumber(held, 4) << " kg by the URDF (fixed to the base: "
              << LinksFixedToBase(robot) << "), which leaves the fit less than "
              << FormatNumber(100.0 * kTotalMassOnset, 2) << " % of it\n";
    return kUsage;
  }
  bound->emplace(TotalMassBound{total, fixed});
  std::cerr << "note: --total-mass " << FormatNumber(total, 6) << " kg: the links' masses plus " << FormatNumber(fixed, 4)
            << " kg fixed to the base (" << LinksFixedToBase(robot) << ") are kept at most it; the URDF's links weigh "
            << FormatNumber(links, 4) << " kg";
  if (fixed + links >= total) {
    std::cerr << ", more than that: the fit starts from their masses scaled down by one factor to "
              << FormatNumber(100.0 * (1.0 - kTotalMassOnset), 3) << " % of it";
  }
  std::cerr << "\n";
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

namespace {

// "mass=2.8" of a --run-payload item into key, value; false if there is no '='.
bool SplitKey(const std::string& part, std::string* key, std::string* value) {
  const std::size_t eq = part.find('=');
  if (eq == std::string::npos) return false;
  *key = part.substr(0, eq);
  *value = part.substr(eq + 1);
  return true;
}

// The body of one --run-payload item from its keys into p->body: the stated body when mass and COM
// are given, else the prior of the fit that finds the rest (p->fitted). Throws
// std::invalid_argument (usage) or InvalidNumber.
void PayloadBody(const std::vector<std::string>& parts, const std::string& item, RunPayload* p) {
  std::optional<double> mass;
  std::optional<Vector3> com;
  std::optional<std::vector<double>> inertia;
  for (size_t k = 1; k < parts.size(); ++k) {
    std::string key, value;
    if (!SplitKey(parts[k], &key, &value)) throw std::invalid_argument("'" + parts[k] + "' is not key=value");
    const std::vector<double> v = ParseNumberList(value, "--run-payload " + key);
    const size_t expected = key == "mass" ? 1 : key == "com" ? 3 : key == "inertia" ? 6 : 0;
    if (expected == 0) throw std::invalid_argument("unknown key '" + key + "' (mass, com, inertia)");
    if (v.size() != expected) throw std::invalid_argument(NumberCountError(key, expected, v.size(), value));
    if (key == "mass") mass = v[0];
    if (key == "com") com = Vector3(v[0], v[1], v[2]);
    if (key == "inertia") inertia = v;
  }
  if (com && !mass) throw std::invalid_argument("a COM without a mass: give mass= too, or neither to fit both");
  if (inertia && !com) throw std::invalid_argument("an inertia about a COM that is not given: give com= too");
  if (mass && !(*mass > 0.0)) throw std::invalid_argument("the mass must be positive");
  p->mass_known = mass.has_value();
  p->fitted = !com.has_value();
  p->known = !p->fitted;
  if (p->fitted) {  // the fit's prior (run_local_bodies.hpp): the stated mass, or half a kilogram, at the link's origin
    p->body = SolidSphere(mass ? *mass : 0.5, 0.05);
    return;
  }
  Matrix3 I_com;
  if (inertia) {
    const std::vector<double>& i = *inertia;
    I_com << i[0], i[3], i[4], i[3], i[1], i[5], i[4], i[5], i[2];
  } else {
    I_com = SolidSphere(*mass, 0.01).rotational_inertia_about_com();
  }
  p->body = InertialParams::FromMassComInertia(*mass, *com, I_com);
  if (!CheckConsistency(p->body).fully_consistent()) {
    throw InvalidNumber("--run-payload " + item + ": the inertia is not that of a real body (its principal moments "
                        "must be positive and each at most the sum of the other two)");
  }
}

}  // namespace

int ParseRunPayloads(const std::vector<std::string>& items, const std::vector<std::string>& files,
                     std::vector<RunPayload>* payloads) {
  for (const std::string& item : items) {
    RunPayload p;
    p.text = item;
    const std::size_t eq = item.find('=');
    try {
      if (eq == std::string::npos) throw std::invalid_argument("expected FILE=LINK[:mass=M[:com=X,Y,Z]]");
      p.file = item.substr(0, eq);
      if (std::find(files.begin(), files.end(), p.file) == files.end()) {
        throw std::invalid_argument("'" + p.file + "' is not one of the --data files (" + RunsName(files) + ")");
      }
      if (std::count(files.begin(), files.end(), p.file) > 1) {
        throw std::invalid_argument("'" + p.file + "' is given more than once as --data, so the payload's run is not one");
      }
      std::vector<std::string> parts;
      std::string rest = item.substr(eq + 1);
      for (std::size_t at; (at = rest.find(':')) != std::string::npos; rest = rest.substr(at + 1)) parts.push_back(rest.substr(0, at));
      parts.push_back(rest);
      p.link = parts[0];
      if (p.link.empty()) throw std::invalid_argument("no link after '='");
      PayloadBody(parts, item, &p);
    } catch (const InvalidNumber& e) {
      std::cerr << "Error: " << e.what() << "\n";
      return kInvalidValue;
    } catch (const std::invalid_argument& e) {
      std::cerr << "Error: --run-payload " << item << ": " << e.what() << "\n";
      return kUsage;
    }
    payloads->push_back(p);
  }
  return kOk;
}

std::string RunsName(const std::vector<std::string>& files) {
  std::string name;
  for (const std::string& f : files) name += (name.empty() ? "" : " + ") + f;
  return name;
}

namespace {

// The torques of the known payloads of the run read from `file` (every column); with `say`, a note of each.
int KnownPayloadTorques(const std::string& file, const JointSamples& log, const std::vector<RunPayload>& payloads,
                        const RobotModel& robot, const Vector3& gravity, bool say, Eigen::MatrixXd* known) {
  *known = Eigen::MatrixXd::Zero(log.size(), log.tau.cols());
  for (const RunPayload& p : payloads) {
    if (p.file != file || !p.known) continue;
    std::vector<EffectSpec> effect = ParseEffectList("payload@" + p.link);
    effect[0].inertia = p.body;
    try {
      const RobotDynamics with(MakeRobotDynamics(robot, effect, gravity));
      *known += BodyTorques(with, static_cast<int>(with.bodies().size()) - 1, log);
    } catch (const std::invalid_argument& e) {
      std::cerr << "Error: --run-payload " << p.text << ": " << e.what() << "\n";
      return kUsage;
    }
    if (say) {
      std::cerr << "note: " << file << ": the torques of the known payload on " << p.link << " (" << p.body.mass()
                << " kg) are taken out of this run's\n";
    }
  }
  return kOk;
}

}  // namespace

int ReadRobotRuns(const std::vector<std::string>& files, std::vector<RunPayload>* payloads, const RobotModel& robot,
                  const Vector3& gravity, const JointCsvOptions& csv, RecordedRuns* runs, std::vector<int>* lines,
                  const LogGains& gains, const RunPayloadFit* fit) {
  std::vector<JointSamples> logs(files.size());
  std::vector<Eigen::MatrixXd> known(files.size());
  for (size_t k = 0; k < files.size(); ++k) {
    std::vector<int> run_lines;
    const int status = ReadRobotLog(files[k], robot, csv, &logs[k], &run_lines);
    if (status != kOk) return status;
    if (lines != nullptr) lines->insert(lines->end(), run_lines.begin(), run_lines.end());
    if (gains.known_gains.size() == logs[k].tau.cols()) {  // the log in N m, by the model file's gains
      logs[k].tau = logs[k].tau * gains.known_gains.cwiseInverse().asDiagonal();
    }
    const int found = KnownPayloadTorques(files[k], logs[k], *payloads, robot, gravity, true, &known[k]);
    if (found != kOk) return found;
  }
  if (std::any_of(payloads->begin(), payloads->end(), [](const RunPayload& p) { return !p.known; })) {
    int status = FitRunPayloads(files, logs, known, robot, gravity, fit != nullptr ? *fit : RunPayloadFit{},
                                gains.fitted, payloads);
    for (size_t k = 0; k < files.size() && status == kOk; ++k) {
      status = KnownPayloadTorques(files[k], logs[k], *payloads, robot, gravity, false, &known[k]);
    }
    if (status != kOk) return status;
  }
  for (size_t k = 0; k < files.size(); ++k) {
    Eigen::MatrixXd taken = known[k];
    for (int d : gains.fitted) taken.col(d).setZero();  // a log to be scaled keeps it: in *known
    logs[k].tau -= taken;
  }
  if (gains.known != nullptr) {
    int rows = 0;
    for (const Eigen::MatrixXd& m : known) rows += static_cast<int>(m.rows());
    gains.known->setZero(rows, robot.tree.num_dofs());
    rows = 0;
    for (const Eigen::MatrixXd& m : known) {
      for (int d : gains.fitted) gains.known->col(d).segment(rows, m.rows()) = m.col(d);
      rows += static_cast<int>(m.rows());
    }
  }
  try {
    *runs = JoinRuns(files, logs);
  } catch (const std::invalid_argument& e) {
    std::cerr << "Error: " << e.what() << "\n";
    return kInvalidValue;
  }
  for (int k = 1; k < runs->num_runs(); ++k) {
    std::cerr << "note: " << files[static_cast<size_t>(k)] << " follows " << files[static_cast<size_t>(k) - 1]
              << " in one log: its times + " << FormatNumber(runs->shifts[static_cast<size_t>(k)], 6) << " s\n";
  }
  return kOk;
}

}  // namespace inertial::cli
