// Per-tick latency of the online estimators (issue 4), names fixed for scripts:
//   Tick/<estimator>/<model>    a whole tick as a controller pays it: features of the sample
//                               (joint-torque regressor and effects, or the body regressor) and
//                               the estimator's update;
//   Update/<estimator>/<model>  the estimator's update alone, features given;
//   TickWithoutQdd/gauss_newton/<model>  Tick/ on a stream whose qdd is not measured: the
//                               filtered momentum rows (momentum_rows.hpp) instead of the features.
// estimator: gauss_newton, gradient, linear_rls (the classical baseline: linear RLS on pi);
// model: body (one body, 10 parameters, 6 measurements), leg3 (examples/leg3.urdf with three
// geared rotors, viscous and Coulomb friction: 66 parameters, 3 measurements), arm7
// (examples/arm7.urdf with viscous and Coulomb friction: 84 parameters, 7 measurements), chain7,
// chain14, chain28 (examples/chain<n>.urdf: serial chains of n revolute joints with alternating
// axes, every link free, viscous and Coulomb friction on every joint: 12 n parameters, n
// measurements), for how the cost grows with the robot.
//   Information/k<k>/<model>    the information form of the linear update, its factor refreshed
//                               every k samples, for the comparison of the two forms' costs;
//   Gemm/<n>x<m>                Eigen's GEMM of the shape of P H^T: the attainable flop rate;
//   TickDiagnosed/<estimator>/<model>  Tick/ as inertiald pays it with the online diagnosis on:
//                               the tick, the copy of the sample and its residual into the
//                               diagnosis's ring (stream_diagnosis.hpp; its worker thread judges on
//                               another core, excitation included) and the payload detector's check
//                               (payload_event.hpp); counter diagnosis_dropped_fraction: samples the
//                               worker had no room for (0: it kept up).
#include <benchmark/benchmark.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <memory>
#include <utility>
#include <vector>

#include "examples/bundled_robots.hpp"
#include "inertial/estimation/online/online_body_estimator.hpp"
#include "inertial/estimation/online/online_joint_estimator.hpp"
#include "inertial/diagnosis/payload_event.hpp"
#include "inertial/diagnosis/stream_diagnosis.hpp"
#include "inertial/inertia/closed_form_bodies.hpp"
#include "inertial/model/fourier_trajectory.hpp"
#include "inertial/model/rigid_body_regressor.hpp"

namespace inertial {
namespace {

constexpr int kSamples = 1000;

// The bundled robots written out in code (the URDFs' own, tests/formats/bundled_robots_test.cpp): this
// program uses the core alone, so that it builds for the robot's computer (scripts/test-aarch64.sh).
RobotDynamics Robot(const std::string& model) {
  if (model == "leg3") {
    return examples::Leg3().Dynamics("viscous,coulomb,rotor@abad:gear=6,rotor@hip:gear=6,rotor@knee:gear=9.33");
  }
  if (model.rfind("chain", 0) == 0) return examples::Chain(std::stoi(model.substr(5))).Dynamics("viscous,coulomb");
  return examples::Arm7().Dynamics("viscous,coulomb");
}

// Samples of a Fourier-series motion with torques of a robot 10 % off the prior (x = 0.1), plus
// noise; the estimators start at that robot, so that the ticks measured are the steady state
// (accepted samples, not rejected outliers of a start far away).
std::vector<JointSample> JointStream(const RobotDynamics& model) {
  const int n = model.num_dofs();
  const Eigen::VectorXd x = Eigen::VectorXd::Constant(model.num_parameters(), 0.1);
  std::vector<JointSample> out;
  const FourierTrajectory reference = RandomFourierTrajectory(n, 5, 0.2, 0.8, 3);
  for (int k = 0; k < kSamples; ++k) {
    const JointTrajectoryPoint p = reference.Evaluate(1e-3 * k);
    JointSample s{1e-3 * k, p.q, p.qd, p.qdd, model.InverseDynamics(x, p.q, p.qd, p.qdd)};
    for (int j = 0; j < n; ++j) s.tau[j] += 0.1 * std::sin(1e3 * k + j);
    out.push_back(s);
  }
  return out;
}

std::vector<BodySample> BodyStream() {
  const InertialParams truth = SolidBox(1.3, 0.2, 0.1, 0.05, Pose{Matrix3::Identity(), Vector3(0.05, 0, 0.02)});
  std::vector<BodySample> out;
  for (int k = 0; k < kSamples; ++k) {
    BodySample s;
    s.t = 1e-3 * k;
    for (int i = 0; i < 6; ++i) {
      const double w = 2 * M_PI * (0.3 + 0.2 * i);
      s.twist[i] = std::sin(w * s.t + i);
      s.acceleration[i] = w * std::cos(w * s.t + i);
    }
    s.has_acceleration = true;
    s.gravity = Vector3(0, 0, -9.81);
    s.wrench = RigidBodyRegressor(s.twist, s.acceleration, s.gravity) * truth.vector();
    for (int i = 0; i < 6; ++i) s.wrench[i] += 0.05 * std::sin(1e3 * k + i);
    out.push_back(s);
  }
  return out;
}

OnlineEstimatorOptions Options(EstimatorKind kind) {
  OnlineEstimatorOptions o;
  o.kind = kind;
  o.measurement_sigma = 0.1;
  o.kalman.forgetting = 0.9999;  // the production setting: forgetting on, so its cost is counted
  return o;
}

// The online fit's tick gates with its last solve's noise and covariance: solved once after its
// warm-up, before the timing, so that the ticks timed run the gate as in production.
void WarmUp(OnlineJointEstimator* est, std::vector<JointSample>* stream, long* k) {
  if (est->fit() == nullptr) return;
  for (; *k < 200; ++*k) est->Update((*stream)[*k % kSamples]);
  est->Solve();
}

void TickJoint(benchmark::State& state, EstimatorKind kind, const std::string& name, bool qdd_measured = true) {
  const RobotDynamics model = Robot(name);
  std::vector<JointSample> stream = JointStream(model);
  for (JointSample& s : stream) s.qdd_measured = qdd_measured;
  OnlineJointEstimator est(model, Eigen::VectorXd::Constant(model.num_parameters(), 0.1), Options(kind));
  long k = 0;
  WarmUp(&est, &stream, &k);
  for (auto _ : state) {
    JointSample& s = stream[k % kSamples];
    s.t = 1e-3 * k++;
    benchmark::DoNotOptimize(est.Update(s));
  }
  state.counters["parameters"] = est.estimator().num_parameters();
  state.counters["measurements"] = model.num_dofs();
  state.counters["accepted_fraction"] = static_cast<double>(est.estimator().counters().accepted()) / k;
}

void TickDiagnosed(benchmark::State& state, EstimatorKind kind, const std::string& name) {
  const RobotDynamics model = Robot(name);
  std::vector<JointSample> stream = JointStream(model);
  const OnlineEstimatorOptions options = Options(kind);
  OnlineJointEstimator est(model, Eigen::VectorXd::Constant(model.num_parameters(), 0.1), options);
  StreamDiagnosis diagnosis(model, StreamDiagnosisOptionsFor(model, options));
  PayloadEventDetector payload(est);
  long k = 0;
  WarmUp(&est, &stream, &k);
  for (auto _ : state) {
    JointSample& s = stream[k % kSamples];
    s.t = 1e-3 * k++;
    if (est.Update(s) == UpdateStatus::kAccepted) diagnosis.Observe(s, est.residual());
    benchmark::DoNotOptimize(payload.Observe(est, s));
  }
  state.counters["parameters"] = est.estimator().num_parameters();
  state.counters["accepted_fraction"] = static_cast<double>(est.estimator().counters().accepted()) / k;
  state.counters["diagnosis_dropped_fraction"] = static_cast<double>(diagnosis.dropped()) / k;
}

void TickBody(benchmark::State& state, EstimatorKind kind) {
  std::vector<BodySample> stream = BodyStream();
  OnlineBodyEstimator est(SolidSphere(1.0, 0.05), Options(kind));
  long k = 0;
  for (auto _ : state) {
    BodySample& s = stream[k % kSamples];
    s.t = 1e-3 * k++;
    benchmark::DoNotOptimize(est.Update(s));
  }
  state.counters["parameters"] = 10;
  state.counters["measurements"] = 6;
  state.counters["accepted_fraction"] = static_cast<double>(est.estimator().counters().accepted()) / k;
}

// The estimator alone on precomputed features.
void UpdateOnly(benchmark::State& state, EstimatorKind kind, const std::string& name) {
  std::vector<Eigen::MatrixXd> A;
  std::vector<Eigen::VectorXd> y;
  std::unique_ptr<RecursiveEstimator> est;
  if (name == "body") {
    for (const BodySample& s : BodyStream()) {
      A.push_back(RigidBodyRegressor(s.twist, s.acceleration, s.gravity));
      y.push_back(s.wrench);
    }
    est = MakeRecursiveEstimator(ParameterLayout::SingleBody(SolidSphere(1.0, 0.05)), 6, Eigen::VectorXd::Zero(10),
                                 Options(kind));
  } else {
    const RobotDynamics model = Robot(name);
    for (const JointSample& s : JointStream(model)) {
      Eigen::MatrixXd a(model.num_dofs(), model.num_features());
      model.Features(s.q, s.qd, s.qdd, a);
      A.push_back(a);
      y.push_back(s.tau);
    }
    est = MakeRecursiveEstimator(ParameterLayout::FromRobot(model), model.num_dofs(),
                                 Eigen::VectorXd::Constant(model.num_parameters(), 0.1), Options(kind));
  }
  long k = 0;
  for (auto _ : state) {
    const int i = k % kSamples;
    benchmark::DoNotOptimize(est->Update(1e-3 * k++, A[i], y[i]));
  }
  state.counters["parameters"] = est->num_parameters();
}

// The information form of the same linear update, measured beside the covariance form
// (Update/linear_rls/<model>) for issue 18, part 2: Y <- lambda Y + H^T H / sigma^2 over each
// measurement's span (a robot's regressor is block-triangular, so this costs sum_i len_i^2 / 2
// in groups of four rows, against the covariance form's n^2 m / 2 downdate and its P H^T),
// g = H^T r / sigma^2, and the step dx = Y^-1 g from a Cholesky factor of Y refreshed every k
// samples (n^3 / 6 every k; two triangular solves, n^2, every sample; between refreshes the factor
// is of an older Y, so the steps are those of less information). Forgetting is one scalar
// (Y = s Yhat). What it lacks: the innovation's Mahalanobis distance (the outlier gate, the change
// detector, Huber's weights) needs H Y^-1 H^T, m triangular solves of n^2 each: the O(n^2 m) this
// form avoids; it is measured here for its cost, not offered as an estimator.
void InformationForm(benchmark::State& state, const std::string& name, int k) {
  const RobotDynamics model = Robot(name);
  const int n = model.num_features(), m = model.num_dofs();
  std::vector<Eigen::MatrixXd> Ht;
  std::vector<Eigen::VectorXd> y;
  for (const JointSample& s : JointStream(model)) {
    Eigen::MatrixXd a(m, n);
    model.Features(s.q, s.qd, s.qdd, a);
    Ht.push_back(a.transpose());
    y.push_back(s.tau);
  }
  // Each group of four measurements' span: the union of its rows' nonzero columns.
  constexpr int kGroup = 4;
  std::vector<std::vector<std::pair<int, int>>> spans(kSamples);
  for (int i = 0; i < kSamples; ++i) {
    for (int g0 = 0; g0 < m; g0 += kGroup) {
      int c = n, e = 0;
      for (int r = g0; r < std::min(g0 + kGroup, m); ++r) {
        for (int j = 0; j < n; ++j) {
          if (Ht[i](j, r) != 0.0) {
            c = std::min(c, j);
            e = std::max(e, j + 1);
          }
        }
      }
      spans[i].push_back({c, e});
    }
  }
  const double sigma = Options(EstimatorKind::kLinearRls).measurement_sigma, lambda = 0.9999;
  Eigen::MatrixXd Y = Eigen::MatrixXd::Identity(n, n);
  Eigen::LLT<Eigen::MatrixXd> llt(Y);
  Eigen::VectorXd w = Eigen::VectorXd::Zero(n), r(m), g(n);
  double scale = 1.0, scale_at_factor = 1.0;
  long t = 0;
  for (auto _ : state) {
    const int i = t % kSamples;
    r = y[i];
    r.noalias() -= Ht[i].transpose() * w;
    scale *= lambda;
    const double weight = 1.0 / (sigma * sigma * scale);
    for (int q = 0; q < static_cast<int>(spans[i].size()); ++q) {
      const auto [c, e] = spans[i][q];
      if (c >= e) continue;
      const int cols = std::min(kGroup, m - q * kGroup);
      Y.block(c, c, e - c, e - c).selfadjointView<Eigen::Lower>().rankUpdate(Ht[i].block(c, q * kGroup, e - c, cols), weight);
    }
    g.noalias() = Ht[i] * r;
    if (t % k == 0) {
      Y *= scale;  // back to Y = Yhat
      scale = 1.0;
      llt.compute(Y);
      scale_at_factor = scale;
    }
    llt.solveInPlace(g);
    w += (scale_at_factor / scale / (sigma * sigma)) * g;
    ++t;
    benchmark::DoNotOptimize(w.data());
  }
  state.counters["parameters"] = n;
}

// The machine's attainable rate for the covariance update's arithmetic: Eigen's blocked GEMM
// C += P G for P n x n and G n x m, the shape of P H^T of each model (2 n^2 m flops), so that a
// tick can be held against flops / rate (the README's bounds of the aims missed). Counter
// `flops`: floating-point operations per second.
void Gemm(benchmark::State& state, int n, int m) {
  const Eigen::MatrixXd P = Eigen::MatrixXd::Random(n, n), G = Eigen::MatrixXd::Random(n, m);
  Eigen::MatrixXd C = Eigen::MatrixXd::Zero(n, m);
  for (auto _ : state) {
    C.noalias() += P * G;
    benchmark::DoNotOptimize(C.data());
    benchmark::ClobberMemory();
  }
  state.counters["flops"] = benchmark::Counter(2.0 * n * n * m, benchmark::Counter::kIsIterationInvariantRate);
}

// The online fit's solve as inertiald's solver thread runs it: warm-started, after the statistics
// grew by 1/8 (solve_growth) since the last solve of 1600 samples; timed alone (the ticks that
// fed the 200 new samples are not).
void SolveOnline(benchmark::State& state, const std::string& name) {
  const RobotDynamics model = Robot(name);
  std::vector<JointSample> stream = JointStream(model);
  OnlineJointEstimator est(model, Eigen::VectorXd::Constant(model.num_parameters(), 0.1), Options(EstimatorKind::kGaussNewton));
  long k = 0;
  for (; k < 1600; ++k) {
    stream[k % kSamples].t = 1e-3 * k;
    est.Update(stream[k % kSamples]);
    if (est.SolveDue()) est.Solve();
  }
  est.Solve();
  long iterations = 0;
  for (auto _ : state) {
    state.PauseTiming();
    for (int i = 0; i < 200; ++i, ++k) {
      stream[k % kSamples].t = 1e-3 * k;
      est.Update(stream[k % kSamples]);
    }
    const OnlineFitSnapshot snapshot = est.fit()->Snapshot();
    state.ResumeTiming();
    const OnlineFitSolution solution = SolveOnlineFit(model, snapshot, est.fit()->options());
    state.PauseTiming();
    iterations += solution.lm.iterations;
    est.Adopt(solution);
    state.ResumeTiming();
  }
  state.counters["parameters"] = model.num_parameters();
  state.counters["lm_iterations"] = static_cast<double>(iterations) / std::max<long>(1, state.iterations());
}

void Register() {
  const std::pair<EstimatorKind, const char*> kinds[] = {{EstimatorKind::kGaussNewton, "gauss_newton"},
                                                         {EstimatorKind::kEkf, "ekf"},
                                                         {EstimatorKind::kGradient, "gradient"},
                                                         {EstimatorKind::kLinearRls, "linear_rls"}};
  for (const char* model : {"leg3", "arm7", "chain7", "chain14", "chain28"}) {
    const std::string m = model;
    benchmark::RegisterBenchmark(("Solve/" + m).c_str(), [m](benchmark::State& s) { SolveOnline(s, m); })
        ->Unit(benchmark::kMillisecond);
  }
  for (const auto& [kind, kname] : kinds) {
    const EstimatorKind k = kind;
    benchmark::RegisterBenchmark((std::string("Tick/") + kname + "/body").c_str(),
                                 [k](benchmark::State& s) { TickBody(s, k); });
    for (const char* model : {"leg3", "arm7", "chain7", "chain14", "chain28"}) {
      const std::string m = model;
      benchmark::RegisterBenchmark((std::string("Tick/") + kname + "/" + m).c_str(),
                                   [k, m](benchmark::State& s) { TickJoint(s, k, m); });
    }
    for (const char* model : {"leg3", "arm7", "chain28"}) {
      const std::string m = model;
      if (k == EstimatorKind::kGaussNewton) {
        benchmark::RegisterBenchmark((std::string("TickWithoutQdd/") + kname + "/" + m).c_str(),
                                     [k, m](benchmark::State& s) { TickJoint(s, k, m, false); });
      }
      benchmark::RegisterBenchmark((std::string("TickDiagnosed/") + kname + "/" + m).c_str(),
                                   [k, m](benchmark::State& s) { TickDiagnosed(s, k, m); });
    }
    for (const char* model : {"body", "leg3", "arm7", "chain7", "chain14", "chain28"}) {
      const std::string m = model;
      if (k == EstimatorKind::kGaussNewton) continue;  // a layout's gauss_newton is the ekf: Tick/ measures the fit
      benchmark::RegisterBenchmark((std::string("Update/") + kname + "/" + m).c_str(),
                                   [k, m](benchmark::State& s) { UpdateOnly(s, k, m); });
    }
  }
  for (const auto& [n, m] : std::vector<std::pair<int, int>>{{10, 6}, {66, 3}, {84, 7}, {168, 14}, {336, 28}}) {
    benchmark::RegisterBenchmark(("Gemm/" + std::to_string(n) + "x" + std::to_string(m)).c_str(),
                                 [n = n, m = m](benchmark::State& s) { Gemm(s, n, m); });
  }
  for (const int k : {1, 10, 100}) {
    for (const char* model : {"leg3", "arm7", "chain7", "chain14", "chain28"}) {
      const std::string m = model;
      benchmark::RegisterBenchmark(("Information/k" + std::to_string(k) + "/" + m).c_str(),
                                   [k, m](benchmark::State& s) { InformationForm(s, m, k); });
    }
  }
}

const bool registered = (Register(), true);

}  // namespace
}  // namespace inertial
