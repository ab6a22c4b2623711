// Per-tick latency of the online estimators (issue 4), names fixed for scripts:
//   Tick/<estimator>/<model>    a whole tick as a controller pays it: features of the sample
//                               (joint-torque regressor and effects, or the body regressor) and
//                               the estimator's update;
//   Update/<estimator>/<model>  the estimator's update alone, features given.
// estimator: gauss_newton, gradient, linear_rls (the classical baseline: linear RLS on pi);
// model: body (one body, 10 parameters, 6 measurements), leg3 (examples/leg3.urdf with three
// geared rotors, viscous and Coulomb friction: 66 parameters, 3 measurements), arm7
// (examples/arm7.urdf with viscous and Coulomb friction: 84 parameters, 7 measurements), chain7,
// chain14, chain28 (examples/chain<n>.urdf: serial chains of n revolute joints with alternating
// axes, every link free, viscous and Coulomb friction on every joint: 12 n parameters, n
// measurements), for how the cost grows with the robot.
#include <benchmark/benchmark.h>

#include <cmath>
#include <memory>

#include "examples/bundled_robots.hpp"
#include "inertial/estimation/online_body_estimator.hpp"
#include "inertial/estimation/online_joint_estimator.hpp"
#include "inertial/inertia/closed_form_bodies.hpp"
#include "inertial/model/fourier_trajectory.hpp"
#include "inertial/model/rigid_body_regressor.hpp"

namespace inertial {
namespace {

constexpr int kSamples = 1000;

// The bundled robots written out in code (the URDFs' own, tests/formats/bundled_robots_test.cpp): this
// program uses the core alone, so that it builds for the robot's computer (scripts/cross-aarch64.sh).
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

void TickJoint(benchmark::State& state, EstimatorKind kind, const std::string& name) {
  const RobotDynamics model = Robot(name);
  std::vector<JointSample> stream = JointStream(model);
  OnlineJointEstimator est(model, Eigen::VectorXd::Constant(model.num_parameters(), 0.1), Options(kind));
  long k = 0;
  for (auto _ : state) {
    JointSample& s = stream[k % kSamples];
    s.t = 1e-3 * k++;
    benchmark::DoNotOptimize(est.Update(s));
  }
  state.counters["parameters"] = est.estimator().num_parameters();
  state.counters["measurements"] = model.num_dofs();
  state.counters["accepted_fraction"] = static_cast<double>(est.estimator().counters().accepted()) / k;
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

void Register() {
  const std::pair<EstimatorKind, const char*> kinds[] = {{EstimatorKind::kGaussNewton, "gauss_newton"},
                                                         {EstimatorKind::kGradient, "gradient"},
                                                         {EstimatorKind::kLinearRls, "linear_rls"}};
  for (const auto& [kind, kname] : kinds) {
    const EstimatorKind k = kind;
    benchmark::RegisterBenchmark((std::string("Tick/") + kname + "/body").c_str(),
                                 [k](benchmark::State& s) { TickBody(s, k); });
    for (const char* model : {"leg3", "arm7", "chain7", "chain14", "chain28"}) {
      const std::string m = model;
      benchmark::RegisterBenchmark((std::string("Tick/") + kname + "/" + m).c_str(),
                                   [k, m](benchmark::State& s) { TickJoint(s, k, m); });
    }
    for (const char* model : {"body", "leg3", "arm7", "chain7", "chain14", "chain28"}) {
      const std::string m = model;
      benchmark::RegisterBenchmark((std::string("Update/") + kname + "/" + m).c_str(),
                                   [k, m](benchmark::State& s) { UpdateOnly(s, k, m); });
    }
  }
}

const bool registered = (Register(), true);

}  // namespace
}  // namespace inertial
