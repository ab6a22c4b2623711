// Joint-space identification costs on the bundled robots: one regressor row block (features of one
// sample), the regressor and A^T A of a 30 s log at 1 kHz, and one Levenberg-Marquardt iteration.
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>

#include "inertial/diagnosis/joint_diagnosis.hpp"
#include "inertial/report/identification_report.hpp"
#include "source_dir.hpp"

namespace inertial {
namespace {

struct Robot {
  RobotModel urdf;
  RobotDynamics model;
};

Robot Load(const std::string& file, const std::string& effects) {
  RobotModel urdf = LoadUrdf(std::string(InertialSourceDir()) + "/examples/" + file);
  RobotDynamics model = MakeRobotDynamics(urdf, ParseEffectList(effects));
  return Robot{std::move(urdf), std::move(model)};
}

// 30 s at 1 kHz of a multi-sine excitation, torques from the model at x (default: the prior) plus
// Gaussian noise of `sigma` N m.
JointSamples Log(const RobotDynamics& model, int samples, const Eigen::VectorXd* x_true = nullptr, double sigma = 0.0) {
  const int n = model.num_dofs();
  JointSamples s;
  s.joint_names = model.dof_names();
  s.t.resize(samples);
  s.q.resize(samples, n);
  s.qd.resize(samples, n);
  s.qdd.resize(samples, n);
  s.tau.resize(samples, n);
  const Eigen::VectorXd x = x_true != nullptr ? *x_true : Eigen::VectorXd::Zero(model.num_parameters());
  std::mt19937 rng(5);
  std::normal_distribution<double> noise(0.0, sigma > 0 ? sigma : 1.0);
  for (int k = 0; k < samples; ++k) {
    const double t = 1e-3 * k;
    s.t[k] = t;
    for (int j = 0; j < n; ++j) {
      const double w = 2 * M_PI * 0.2 * (1 + 0.3 * j);
      s.q(k, j) = 0.8 * std::sin(w * t + j);
      s.qd(k, j) = 0.8 * w * std::cos(w * t + j);
      s.qdd(k, j) = -0.8 * w * w * std::sin(w * t + j);
    }
    s.tau.row(k) = model.InverseDynamics(x, s.q.row(k).transpose(), s.qd.row(k).transpose(), s.qdd.row(k).transpose()).transpose();
    if (sigma > 0) {
      for (int j = 0; j < n; ++j) s.tau(k, j) += sigma * noise(rng);
    }
  }
  return s;
}

void RegressorRows(benchmark::State& state, const std::string& file, const std::string& effects) {
  const Robot r = Load(file, effects);
  const JointSamples s = Log(r.model, 100);
  Eigen::MatrixXd A(r.model.num_dofs(), r.model.num_features());
  int k = 0;
  for (auto _ : state) {
    r.model.Features(s.q.row(k).transpose(), s.qd.row(k).transpose(), s.qdd.row(k).transpose(), A);
    benchmark::DoNotOptimize(A.data());
    k = (k + 1) % 100;
  }
  state.counters["features"] = r.model.num_features();
}
BENCHMARK_CAPTURE(RegressorRows, leg3, "leg3.urdf", "");
BENCHMARK_CAPTURE(RegressorRows, arm7, "arm7.urdf", "");

void NormalEquations30s(benchmark::State& state, const std::string& file, const std::string& effects) {
  const Robot r = Load(file, effects);
  const JointSamples s = Log(r.model, 30000);
  for (auto _ : state) benchmark::DoNotOptimize(AccumulateNormalEquations(r.model, s).AtA.data());
}
BENCHMARK_CAPTURE(NormalEquations30s, arm7_viscous_coulomb, "arm7.urdf", "viscous,coulomb")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(NormalEquations30s, leg3_rotors, "leg3.urdf", "viscous,coulomb,rotor@abad:gear=6,rotor@hip:gear=6,rotor@knee:gear=9")
    ->Unit(benchmark::kMillisecond);

void OneLevenbergMarquardtIteration(benchmark::State& state, const std::string& file, const std::string& effects) {
  const Robot r = Load(file, effects);
  const JointNormalEquations eq = AccumulateNormalEquations(r.model, Log(r.model, 30000));
  JointIdentificationOptions options;
  options.lm.max_iterations = 1;
  for (auto _ : state) benchmark::DoNotOptimize(IdentifyJointModel(r.model, eq, options).x.data());
  state.counters["parameters"] = r.model.num_parameters();
}
BENCHMARK_CAPTURE(OneLevenbergMarquardtIteration, arm7_viscous_coulomb, "arm7.urdf", "viscous,coulomb")->Unit(benchmark::kMicrosecond);

// The whole of `inertial identify` minus file reading: a 30 s log at 1 kHz of the 7-DOF arm whose
// links differ from the URDF prior (theta uniform in [-0.2, 0.2]) with friction, 0.3 N m noise;
// regressor, A^T A, the fit, the prior's and the fit's errors and the identifiability analysis.
void Identify30s(benchmark::State& state, const std::string& file, const std::string& effects) {
  const Robot r = Load(file, effects);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-0.2, 0.2);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(r.model.num_parameters());
  for (int i = 0; i < 10 * static_cast<int>(r.model.bodies().size()); ++i) x[i] = u(rng);
  for (int i = 10 * static_cast<int>(r.model.bodies().size()); i < x.size(); ++i) x[i] = std::log(0.3);
  const JointSamples log = Log(r.model, 30000, &x, 0.3);
  int iterations = 0;
  bool converged = true;
  for (auto _ : state) {
    const IdentificationRun run = RunIdentification(r.model, log, nullptr, JointIdentificationOptions());
    iterations = run.fit.lm.iterations;
    converged = converged && run.fit.lm.converged();
  }
  state.counters["iterations"] = iterations;
  state.counters["converged"] = converged;
}
BENCHMARK_CAPTURE(Identify30s, arm7_viscous_coulomb, "arm7.urdf", "viscous,coulomb")->Unit(benchmark::kMillisecond);

// `inertial diagnose` minus file reading, with the whole candidate catalog: the 7-DOF arm (links
// perturbed, Coulomb friction on joint 6), 30 s at 1 kHz for training and 9 s held out; the model
// fit plus 35 candidate fits (viscous, coulomb, offset, armature, spring on 7 joints), on one
// thread and on all (threads = 0).
void Diagnose30s(benchmark::State& state, int threads) {
  const Robot r = Load("arm7.urdf", "coulomb@joint6");
  Eigen::VectorXd x = Eigen::VectorXd::Zero(r.model.num_parameters());
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-0.2, 0.2);
  for (int i = 0; i < 10 * static_cast<int>(r.model.bodies().size()); ++i) x[i] = u(rng);
  x[x.size() - 1] = std::log(0.3);
  const JointSamples all = Log(r.model, 39000, &x, 0.1);
  JointSamples train, validation;
  SplitHoldout(all, 9000.0 / 39000.0, &train, &validation);
  const RobotModelFactory make = [&r](const std::vector<EffectSpec>& e) { return MakeRobotDynamics(r.urdf, e); };
  JointDiagnosisOptions options;
  options.threads = threads;
  int candidates = 0, suggestions = 0;
  bool top_right = false;
  for (auto _ : state) {
    const JointDiagnosis d = DiagnoseJointModel(make, {}, r.urdf.body_links, train, validation, options);
    candidates = static_cast<int>(d.candidates.size());
    suggestions = d.num_suggestions;
    top_right = suggestions > 0 && d.candidates[0].name == "coulomb@joint6";
  }
  state.counters["candidates"] = candidates;
  state.counters["suggestions"] = suggestions;
  state.counters["top_is_coulomb_joint6"] = top_right;
}
BENCHMARK_CAPTURE(Diagnose30s, arm7_one_thread, 1)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(Diagnose30s, arm7_all_threads, 0)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace inertial
