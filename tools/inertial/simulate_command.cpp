// `inertial simulate`: joint logs of a URDF robot (with any effects) tracking a Fourier excitation,
// by the project's forward-dynamics simulator, in the CSV contract that `identify` reads.
#include <cerrno>
#include <cmath>
#include <fstream>
#include <iostream>
#include <optional>
#include <nlohmann/json.hpp>
#include <random>

#include "commands.hpp"
#include "inertial/config/motors_yaml.hpp"
#include "inertial/formats/file_error.hpp"
#include "inertial/formats/model_file.hpp"
#include "exit_codes.hpp"
#include "progress.hpp"
#include "inertial/formats/joint_csv.hpp"
#include "inertial/transport/can_joint_assembler.hpp"
#include "inertial/transport/joint_message.hpp"
#include "inertial/model/fourier_trajectory.hpp"
#include "inertial/model/joint_limits.hpp"
#include "inertial/model/joint_simulation.hpp"
#include "option_parsing.hpp"

namespace inertial::cli {

CLI::App* AddSimulateCommand(CLI::App& app, SimulateCommand* c) {
  CLI::App* sub = app.add_subcommand(
      "simulate",
      "Simulate a URDF robot (its links, optionally perturbed, plus --effects) tracking a random Fourier-series "
      "excitation (Swevers et al. 1997) under computed-torque PD control, integrated by RK4 (more steps where the "
      "robot's loop or friction is stiff); writes the joint log "
      "in the CSV contract of `identify` (t, q_J, qd_J, qdd_J, tau_J), with optional Gaussian noise.");
  sub->add_option("--model", c->model, "URDF robot description")->required();
  sub->add_option("--out", c->out, "the CSV log to write");
  sub->add_option("--write-log", c->write_log,
                  "also (or instead) write the stream as an LCM log of inertial.joint_state_t (as lcm-logger would)");
  sub->add_option("--log-channel", c->log_channel, "channel of --write-log")->default_val("INERTIAL_JOINT_STATE");
  sub->add_option("--write-candump", c->write_candump,
                  "also write the motors' reply frames (--can-config) as a candump -l log on can0");
  sub->add_option("--can-config", c->can_config, "motors.yaml for --write-candump");
  sub->add_option("--effects", c->effects, "effects in the true robot (syntax of identify --effects)");
  sub->add_option("--effect-values", c->effect_values,
                  "true coefficients, one per effect term in list order (an effect without @ gives one term per "
                  "joint; spring takes k then k q0, asymmetric bp then bn), cycled if fewer; default 0.1 each")
      ->default_val("0.1");
  sub->add_option("--perturb", c->perturb,
                  "true bodies: each link's log-Cholesky theta relative to its URDF body (eq. 11, U = e^alpha [A t; 0 1]) "
                  "drawn uniform in [-P, P]: the mass is scaled by e^(2 alpha), between e^(-2P) and e^(2P); the mass "
                  "distribution is stretched by e^(d_i) along the link frame's axes and sheared by s_ij (A); the COM c0 "
                  "moves to A c0 + t, t up to P metres along each axis (so --perturb 0.2 moves COMs by up to 20 cm); "
                  "every true body is physically consistent, and one that leaves the region its link could occupy (its "
                  "collision shapes or its joints, as identify's) is pulled back toward the URDF until it is well inside; "
                  "0: the URDF")
      ->default_val("0");
  sub->add_option("--duration", c->duration, "seconds of log")->default_val("20");
  sub->add_option("--rate", c->rate, "sample rate [Hz]")->default_val("500");
  sub->add_option("--start-time", c->start_time,
                  "time of the first sample [s] (the excitation runs from there: logs that continue one another)")
      ->default_val("0");
  sub->add_option("--harmonics", c->harmonics, "harmonics of the excitation")->default_val("5");
  sub->add_option("--base-frequency", c->base_frequency, "base frequency of the excitation [Hz]")->default_val("0.1");
  sub->add_option("--amplitude", c->amplitude,
                  "bound of every joint's excursion [rad or m] about the middle of its URDF range; a joint whose "
                  "<limit> range or velocity is smaller gets its excitation scaled to 95 % of it (a note says so), "
                  "and a log beyond a position, velocity or effort limit is refused")
      ->default_val("0.9");
  sub->add_flag("--ignore-limits", c->ignore_limits,
                "excite every joint about q = 0 with the full --amplitude, whatever the URDF's <limit>s say");
  sub->add_option("--noise-q", c->noise_q, "standard deviation of position noise [rad or m]")->default_val("0");
  sub->add_option("--noise-qd", c->noise_qd, "standard deviation of velocity noise")->default_val("0");
  sub->add_option("--noise-tau", c->noise_tau, "standard deviation of torque noise [N m or N]")->default_val("0");
  sub->add_option("--seed", c->seed, "random seed of the trajectory and the noise")->default_val("1");
  sub->add_option("--truth-seed", c->truth_seed,
                  "random seed of the perturbed bodies (keep it to simulate train and test logs of one robot)")
      ->default_val("1");
  sub->add_flag("--positions-only", c->positions_only,
                "write only t, q_J, tau_J (identify then differentiates q by Savitzky-Golay)");
  sub->add_option("--truth", c->truth, "also write the true parameters as JSON (bodies' pi, effect values)");
  sub->add_option("--truth-urdf", c->truth_urdf,
                  "also write the true robot as a model file (URDF with its effects: validate --model reads it)");
  return sub;
}

namespace {

// The numeric options of simulate, parsed (ParseSimulateSettings).
struct SimulateSettings {
  double perturb = 0, duration = 0, start_time = 0, rate = 0, base_frequency = 0, amplitude = 0;
  SampleNoise noise;
  int harmonics = 0;
  std::uint64_t seed = 0, truth_seed = 0;
  std::vector<double> effect_values;
};

int ParseSimulateSettings(const SimulateCommand& c, SimulateSettings* s) {
  int status = ParseRealOption(c.perturb, "--perturb", 0.0, 5.0, &s->perturb);
  if (status == kOk) status = ParseRealOption(c.duration, "--duration", 1e-3, 1e6, &s->duration);
  if (status == kOk) status = ParseRealOption(c.start_time, "--start-time", -1e9, 1e9, &s->start_time);
  if (status == kOk) status = ParseRealOption(c.rate, "--rate", 1.0, 1e6, &s->rate);
  if (status == kOk) status = ParseInteger(c.harmonics, "--harmonics", 1, 100, &s->harmonics);
  if (status == kOk) status = ParseRealOption(c.base_frequency, "--base-frequency", 1e-6, 1e3, &s->base_frequency);
  if (status == kOk) status = ParseRealOption(c.amplitude, "--amplitude", 1e-9, 1e3, &s->amplitude);
  if (status == kOk) status = ParseRealOption(c.noise_q, "--noise-q", 0.0, 1e6, &s->noise.q);
  if (status == kOk) status = ParseRealOption(c.noise_qd, "--noise-qd", 0.0, 1e6, &s->noise.qd);
  if (status == kOk) status = ParseRealOption(c.noise_tau, "--noise-tau", 0.0, 1e6, &s->noise.tau);
  if (status == kOk) status = ParseInteger<std::uint64_t>(c.seed, "--seed", 0, UINT64_MAX, &s->seed);
  if (status == kOk) status = ParseInteger<std::uint64_t>(c.truth_seed, "--truth-seed", 0, UINT64_MAX, &s->truth_seed);
  if (status != kOk) return status;
  try {
    s->effect_values = ParseNumberList(c.effect_values, "--effect-values");
  } catch (const InvalidNumber& e) {
    std::cerr << "Error: " << e.what() << "\n";
    return kInvalidValue;
  }
  if (s->effect_values.empty()) {
    std::cerr << "Error: --effect-values: no value given\n";
    return kUsage;
  }
  return kOk;
}

// The output files, checked before anything is simulated.
int CheckSimulateOutputs(const SimulateCommand& c) {
  if (RefuseOverwritingInputs({{"--out", c.out}, {"--write-log", c.write_log}, {"--write-candump", c.write_candump},
                               {"--truth", c.truth}, {"--truth-urdf", c.truth_urdf}},
                              {{"--model", c.model}, {"--can-config", c.can_config}}) != kOk) {
    return kUsage;
  }
  if (c.out.empty() && c.write_log.empty() && c.write_candump.empty()) {
    std::cerr << "Error: give --out CSV, --write-log LCM and/or --write-candump LOG\n";
    return kUsage;
  }
  if (c.write_candump.empty() != c.can_config.empty()) {
    std::cerr << "Error: --write-candump and --can-config go together\n";
    return kUsage;
  }
  return kOk;
}

// The true parameters: the effects' coefficients (cycled from --effect-values) and each link's
// theta relative to its URDF body drawn uniform in [-P, P] (0: the URDF's bodies).
int TrueParameters(const RobotDynamics& model, const SimulateSettings& s, Eigen::VectorXd* x) {
  const int n_effect = model.num_features() - model.num_inertia_features();
  Eigen::VectorXd coefficients(n_effect);
  for (int k = 0; k < n_effect; ++k) coefficients[k] = s.effect_values[k % s.effect_values.size()];
  for (const EffectTerm& t : model.effects()) {
    // Every coefficient is non-negative but an offset's and a spring's k q0.
    const int non_negative = t.kind == EffectKind::kOffset ? 0 : t.kind == EffectKind::kSpring ? 1 : t.size();
    for (int i = 0; i < non_negative; ++i) {
      if (coefficients[t.first_feature + i - model.num_inertia_features()] < 0) {
        std::cerr << "Error: --effect-values: " << ToString(t.kind) << "@" << t.joint << " must be >= 0\n";
        return kInvalidValue;
      }
    }
  }
  *x = model.ParametersFromEffectCoefficients(coefficients, 1e-300);
  std::mt19937_64 rng(s.truth_seed);
  std::uniform_real_distribution<double> uniform(-s.perturb, s.perturb);
  for (int i = 0; i < 10 * static_cast<int>(model.bodies().size()); ++i) (*x)[i] = s.perturb > 0 ? uniform(rng) : 0.0;
  // The true robot's links stay inside the regions they could occupy (body_region.hpp): a draw
  // that leaves one is pulled back toward the URDF until it is well inside.
  for (size_t e = 0; e < model.bodies().size(); ++e) {
    const EstimatedBody& b = model.bodies()[e];
    if (b.region) x->segment<10>(10 * static_cast<int>(e)) = ShrinkIntoRegion(b.map, *b.region, x->segment<10>(10 * static_cast<int>(e)));
  }
  return kOk;
}

// Fraction of every limit left free for the tracking error and for peaks between samples. The
// tracking loop feeds the plant's own inverse dynamics forward, so it deviates only by the
// zero-order hold of the command (a fraction of a percent of the excursion); 5 % is ample and
// costs the excitation little.
constexpr double kLimitMargin = 0.05;

// The excitation of every joint, centred in its URDF position range and scaled (with a note on
// stderr) to keep within its position and velocity limits unless --ignore-limits.
FourierTrajectory Excitation(const RobotModel& robot, const RobotDynamics& model, const SimulateSettings& s,
                             bool ignore_limits) {
  FourierTrajectory reference =
      RandomFourierTrajectory(model.num_dofs(), s.harmonics, s.base_frequency, s.amplitude, s.seed);
  if (ignore_limits) return reference;
  const int n = static_cast<int>(std::floor(s.duration * s.rate + 1e-9)) + 1;
  const Eigen::VectorXd t = Eigen::VectorXd::LinSpaced(n, 0.0, (n - 1) / s.rate).array() + s.start_time;
  for (const LimitedExcitation& l : FitExcitationToLimits(robot.dof_limits, t, kLimitMargin, &reference)) {
    const JointLimits& lim = robot.dof_limits[l.joint];
    std::cerr << "note: joint '" << model.dof_names()[l.joint] << "': excitation scaled by " << l.scale << " to keep ";
    if (l.kind == LimitKind::kVelocity) {
      std::cerr << "|qd| within its velocity limit " << lim.velocity << "\n";
    } else {
      std::cerr << "q within its range [" << lim.lower << ", " << lim.upper << "]\n";
    }
  }
  return reference;
}

// A simulated log that left its excitation (a diverged integration) or a URDF limit is refused.
int CheckSimulatedLog(const RobotModel& robot, const FourierTrajectory& reference, const JointSamples& samples,
                      double amplitude, bool ignore_limits) {
  double worst_tracking = 0.0;
  for (int i = 0; i < samples.size(); ++i) {
    worst_tracking = std::max(
        worst_tracking, (samples.q.row(i).transpose() - reference.Evaluate(samples.t[i]).q).cwiseAbs().maxCoeff());
  }
  if (!(worst_tracking < 0.1 * amplitude)) {
    std::cerr << "Error: simulation failed: the robot left the excitation trajectory by " << worst_tracking
              << " (more than 10 % of --amplitude); try a smaller --perturb or a higher --rate\n";
    return kInvalidValue;
  }
  if (ignore_limits) return kOk;
  if (const std::optional<LimitViolation> v = FirstLimitViolation(samples, robot.dof_limits)) {
    const std::string joint = samples.joint_names[v->joint];
    std::cerr << "Error: simulation refused: at t = " << v->time << " s joint '" << joint
              << "' " << (v->kind == LimitKind::kPosition ? "is at q = " : v->kind == LimitKind::kVelocity ? "moves at qd = " : "needs tau = ")
              << v->value << ", beyond its URDF " << ToString(v->kind) << " limit " << v->limit
              << "; lower --amplitude or --base-frequency (or give --ignore-limits)\n";
    return kInvalidValue;
  }
  return kOk;
}

// The robot tracking its excitation (RK4, computed-torque control, steps cut where the loop or the
// friction is stiff).
int Simulate(const RobotDynamics& model, const Eigen::VectorXd& x, const FourierTrajectory& reference,
             const SimulateSettings& s, JointSamples* samples) {
  const Eigen::VectorXd w = model.Coefficients(x);  // once: the plant is called four times per RK4 step and DOF
  const JointDynamicsFn plant = [&](const Eigen::VectorXd& q, const Eigen::VectorXd& qd, const Eigen::VectorXd& qdd) {
    return model.InverseDynamicsFromCoefficients(w, q, qd, qdd);
  };
  JointSimulationOptions options;
  options.duration = s.duration;
  options.start_time = s.start_time;
  options.sample_rate_hz = s.rate;
  options.internal_step = std::min(5e-4, 1.0 / s.rate);
  Progress progress("simulate");
  options.progress = [&](double f) { progress.Fraction(f); };
  // Computed torque with the true robot: every joint's error a 5 Hz, 0.7-damped loop, whatever the
  // robot; the simulator adds steps wherever the friction is stiffer than 5e-4 s steps follow.
  const double bandwidth = 2 * M_PI * 5.0;
  options.kp = Eigen::VectorXd::Constant(1, bandwidth * bandwidth);
  options.kd = Eigen::VectorXd::Constant(1, 2 * 0.7 * bandwidth);
  try {
    *samples = SimulateTracking(plant, plant, [&](double t) { return reference.Evaluate(t); }, options,
                                model.dof_names());
    progress.Done();
  } catch (const SimulationDiverged& e) {
    std::cerr << "Error: " << e.what() << "\n";
    return kInvalidValue;
  } catch (const std::invalid_argument& e) {
    std::cerr << "Error: simulation failed: " << e.what() << "\n";
    return kInvalidValue;
  }
  return kOk;
}

int WriteSamples(const SimulateCommand& c, const std::optional<CanConfig>& can, const JointSamples& samples) {
  try {
    if (!c.write_log.empty()) WriteJointStateLog(c.write_log, c.log_channel, samples, !c.positions_only);
    if (can) WriteMotorCandump(c.write_candump, "can0", *can, samples);
  } catch (const std::runtime_error& e) {
    std::cerr << "Error: " << e.what() << "\n";
    return kIoError;
  } catch (const std::invalid_argument& e) {
    std::cerr << "Error: --can-config: " << e.what() << "\n";
    return kUsage;
  }
  try {
    if (c.out.empty()) {
      // only the LCM log
    } else if (c.positions_only) {
      const int n = static_cast<int>(samples.joint_names.size());
      Eigen::MatrixXd columns(samples.size(), 1 + 2 * n);
      columns << samples.t, samples.q, samples.tau;
      std::vector<std::string> header{"t"};
      for (const std::string& j : samples.joint_names) header.push_back("q_" + j);
      for (const std::string& j : samples.joint_names) header.push_back("tau_" + j);
      WriteColumnsCsv(c.out, header, columns);
    } else {
      WriteJointCsv(c.out, samples);
    }
  } catch (const CsvError& e) {
    std::cerr << "Error: " << e.what() << "\n";
    return ExitCodeOf(e);
  }
  return kOk;
}

int WriteTruthJson(const std::string& path, const RobotDynamics& model, const Eigen::VectorXd& x) {
  nlohmann::json j;
  nlohmann::json bodies = nlohmann::json::array();
  for (int e = 0; e < static_cast<int>(model.bodies().size()); ++e) {
    const InertialParams b = model.BodyInertia(e, x);
    bodies.push_back({{"name", model.bodies()[e].name},
                      {"pi", std::vector<double>(b.vector().data(), b.vector().data() + 10)},
                      {"theta", std::vector<double>(x.data() + 10 * e, x.data() + 10 * e + 10)}});
  }
  nlohmann::json effects = nlohmann::json::array();
  for (int k = 0; k < static_cast<int>(model.effects().size()); ++k) {
    effects.push_back({{"effect", std::string(ToString(model.effects()[k].kind))},
                       {"joint", model.effects()[k].joint},
                       {"values", model.EffectValues(k, x)}});
  }
  j["bodies"] = bodies;
  j["effects"] = effects;
  j["x"] = std::vector<double>(x.data(), x.data() + x.size());
  errno = 0;
  std::ofstream out(path);
  out << j.dump(2) << "\n";
  out.flush();
  if (!out) {
    std::cerr << "Error: --truth: " << CannotText("write", "", path) << "\n";
    return kIoError;
  }
  return kOk;
}

int WriteTruth(const SimulateCommand& c, const RobotModel& robot, const RobotDynamics& model, const Eigen::VectorXd& x) {
  if (!c.truth_urdf.empty()) {
    try {
      WriteModelUrdf(c.model, c.truth_urdf, robot, model, SnapshotAt(model, x),
                     "the true model of `inertial simulate` (--perturb " + c.perturb + ", --truth-seed " + c.truth_seed + ")");
    } catch (const UrdfError& e) {
      std::cerr << "Error: " << e.what() << "\n";
      return kIoError;
    }
  }
  return c.truth.empty() ? kOk : WriteTruthJson(c.truth, model, x);
}

int LoadSimulateInputs(const SimulateCommand& c, std::optional<CanConfig>* can, RobotModel* robot,
                       std::optional<RobotDynamics>* model) {
  if (!c.can_config.empty()) {
    try {
      *can = LoadCanConfig(c.can_config);
    } catch (const std::exception& e) {  // cannot be read, or not a valid motors.yaml: a file error
      std::cerr << "Error: --can-config: " << e.what() << "\n";
      return kIoError;
    }
  }
  try {
    *robot = LoadUrdf(c.model);
  } catch (const UrdfError& e) {
    std::cerr << "Error: " << e.what() << "\n";
    return kIoError;
  }
  try {
    model->emplace(MakeRobotDynamics(*robot, ParseEffectList(c.effects)));
  } catch (const std::invalid_argument& e) {
    std::cerr << "Error: --effects: " << e.what() << "\n";
    return kUsage;
  }
  return kOk;
}

}  // namespace

int RunSimulateCommand(const SimulateCommand& c) {
  int status = CheckSimulateOutputs(c);
  SimulateSettings s;
  if (status == kOk) status = ParseSimulateSettings(c, &s);
  std::optional<CanConfig> can;
  RobotModel robot;
  std::optional<RobotDynamics> model;
  if (status == kOk) status = LoadSimulateInputs(c, &can, &robot, &model);
  Eigen::VectorXd x;
  if (status == kOk) status = TrueParameters(*model, s, &x);
  if (status != kOk) return status;
  FourierTrajectory reference;
  try {
    reference = Excitation(robot, *model, s, c.ignore_limits);
  } catch (const std::invalid_argument& e) {
    std::cerr << "Error: " << c.model << ": " << e.what() << "\n";
    return kInvalidValue;
  }
  JointSamples samples;
  status = Simulate(*model, x, reference, s, &samples);
  if (status == kOk) status = CheckSimulatedLog(robot, reference, samples, s.amplitude, c.ignore_limits);
  if (status != kOk) return status;
  samples = AddGaussianNoise(samples, s.noise, s.seed + 1);
  status = WriteSamples(c, can, samples);
  if (status == kOk) status = WriteTruth(c, robot, *model, x);
  if (status != kOk) return status;
  std::string written;
  for (const std::string* f : {&c.out, &c.write_log, &c.write_candump}) {
    if (!f->empty()) written += (written.empty() ? "" : " and ") + *f;
  }
  std::cerr << "wrote " << written << ": " << samples.size() << " samples of " << model->num_dofs() << " joints, "
            << s.duration << " s at " << s.rate << " Hz\n";
  return kOk;
}

}  // namespace inertial::cli
