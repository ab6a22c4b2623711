#include "inertial/study/paper_study.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <functional>
#include <limits>
#include <memory>
#include <random>
#include <stdexcept>
#include <thread>

#include "inertial/estimation/batch/linear_least_squares.hpp"
#include "inertial/inertia/closed_form_bodies.hpp"
#include "inertial/inertia/positive_eigenvalue_parameterization.hpp"
#include "inertial/inertia/exponential_parameterization.hpp"
#include "inertial/inertia/linear_parameterization.hpp"
#include "inertial/inertia/log_cholesky.hpp"
#include "inertial/model/midpoint_regression.hpp"

namespace inertial {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Independent streams per (seed, body, purpose).
std::mt19937_64 BodyGenerator(std::uint64_t seed, int body_index, int purpose) {
  std::seed_seq seq{static_cast<std::uint32_t>(seed), static_cast<std::uint32_t>(seed >> 32),
                    static_cast<std::uint32_t>(body_index), static_cast<std::uint32_t>(purpose)};
  return std::mt19937_64(seq);
}

double Median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 == 1 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

double RelativeParameterError(const Vector10& pi, const Vector10& truth) { return (pi - truth).norm() / truth.norm(); }

}  // namespace

std::string_view StudyMethodName(int method) {
  switch (method) {
    case kLinear: return "linear";
    case kEigenvalue: return "eigenvalue";
    case kExponential: return "exponential";
    case kLogCholesky: return "log_cholesky";
    default: return "unknown";
  }
}

Vector6 StudyWrench(double t) {
  Vector6 w;
  for (int k = 0; k < 6; ++k) w[k] = std::sin(t + k * kPi / 3.0);
  return w;
}

InertialParams SampleTableIBody(std::uint64_t seed, int body_index) {
  std::mt19937_64 gen = BodyGenerator(seed, body_index, 0);
  auto uniform = [&gen](double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(gen); };
  // z, then y, then x: the order in which x86-64's GCC evaluated Vector3(uniform(..), uniform(..),
  // uniform(..)) (right to left; aarch64's goes left to right), so that both draw the same bodies.
  auto uniform3 = [&uniform](double lo, double hi) {
    const double z = uniform(lo, hi);
    const double y = uniform(lo, hi);
    const double x = uniform(lo, hi);
    return Vector3(x, y, z);
  };
  const double m = uniform(0.01, 1.0);
  const Vector3 c = uniform3(-0.5, 0.5);
  const Vector3 L = uniform3(0.01, 1.0);
  Vector3 beta;
  do {  // uniform in the ball of radius 2 pi, by rejection from the cube
    beta = uniform3(-2 * kPi, 2 * kPi);
  } while (beta.norm() > 2 * kPi);
  Pose pose;
  const double angle = beta.norm();
  pose.R_BC = angle > 0.0 ? Matrix3(Eigen::AngleAxisd(angle, beta / angle)) : Matrix3::Identity();
  pose.p_BoCo_B = c;
  return BodyFromSecondMoments(m, L, pose);
}

std::vector<TwistWrenchSample> SimulateStudyBody(const InertialParams& body, std::uint64_t seed, int body_index,
                                                 const StudyOptions& options, int* integrator_steps) {
  std::vector<double> times;
  for (int k = 0;; ++k) {
    const double t = k * options.sample_interval;
    if (t > options.duration + 1e-12) break;
    times.push_back(t);
  }
  const SimulationResult sim = SimulateRigidBody(body, Vector6::Zero(), StudyWrench, times, options.integrator);
  if (!sim.ok) throw std::runtime_error("study: integration failed for body " + std::to_string(body_index));
  if (integrator_steps != nullptr) *integrator_steps = sim.accepted_steps + sim.rejected_steps;
  std::mt19937_64 gen = BodyGenerator(seed, body_index, 1);
  std::uniform_real_distribution<double> noise(options.noise_bias - 0.5 * options.noise_width,
                                               options.noise_bias + 0.5 * options.noise_width);
  std::vector<TwistWrenchSample> samples(times.size());
  for (std::size_t i = 0; i < times.size(); ++i) {
    samples[i].t = times[i];
    for (int k = 0; k < 6; ++k) samples[i].twist[k] = sim.twists[i][k] + noise(gen);
    samples[i].wrench = StudyWrench(times[i]);
  }
  return samples;
}

namespace {

using StudyMaps = std::array<const Parameterization*, kStudyMethods>;

// Body `index` of the study: drawn, simulated, fitted by linear least squares and by each
// parameterization from its start; then which consistent fits stopped short of the best cost.
void StudyBody(const StudyOptions& options, const StudyMaps& parameterizations,
               const std::array<Vector10, kStudyMethods>& x_start, int index, BodyOutcome& out) {
  const InertialParams truth = SampleTableIBody(options.seed, index);
  out.pi_true = truth.vector();
  const std::vector<TwistWrenchSample> samples =
      SimulateStudyBody(truth, options.seed, index, options, &out.integrator_steps);
  const LinearRegression regression = BuildMidpointRegression(samples);
  const LinearLeastSquaresResult lls = SolveLinearLeastSquares(regression);
  out.pi_linear_ls = lls.pi;
  out.linear_ls_cost = lls.cost;
  out.linear_ls_report = CheckConsistency(InertialParams::FromVector(lls.pi));
  out.linear_ls_parameter_error = RelativeParameterError(lls.pi, out.pi_true);
  for (int k = 0; k < kStudyMethods; ++k) {
    const auto t0 = std::chrono::steady_clock::now();
    const LevenbergMarquardtResult fit =
        FitLevenbergMarquardt(*parameterizations[k], regression, x_start[k], options.solver);
    const auto t1 = std::chrono::steady_clock::now();
    MethodOutcome& m = out.methods[k];
    m.seconds = std::chrono::duration<double>(t1 - t0).count();
    m.iterations = fit.iterations;
    m.reason = fit.reason;
    m.cost = fit.cost;
    m.pi = fit.pi;
    m.consistent = parameterizations[k]->YieldsConsistentBody(fit.x);
    m.near_degenerate = m.consistent && !IsPhysicallyConsistent(InertialParams::FromVector(fit.pi));
    m.failed = !fit.converged() || (k != kLinear && !m.consistent);
    m.parameter_error = RelativeParameterError(fit.pi, out.pi_true);
  }
  // The best cost any consistent method reached on this body.
  double best = std::numeric_limits<double>::infinity();
  for (int k = kEigenvalue; k < kStudyMethods; ++k) {
    if (out.methods[k].consistent) best = std::min(best, out.methods[k].cost);
  }
  for (int k = kEigenvalue; k < kStudyMethods; ++k) {
    MethodOutcome& m = out.methods[k];
    m.suboptimal = m.consistent && m.cost > best * (1.0 + kSuboptimalRelativeCost);
  }
}

// body(i) for i in [0, count) on `threads` threads (0: one per core); the first exception rethrown.
void ForEachBodyInParallel(int count, int threads_asked, const std::function<void(int)>& body) {
  const int threads = std::max(
      1, std::min(threads_asked > 0 ? threads_asked : static_cast<int>(std::thread::hardware_concurrency()), count));
  std::atomic<int> next{0};
  std::vector<std::exception_ptr> errors(threads);
  std::vector<std::thread> pool;
  for (int w = 0; w < threads; ++w) {
    pool.emplace_back([&, w] {
      try {
        for (int i = next++; i < count; i = next++) body(i);
      } catch (...) {
        errors[w] = std::current_exception();
      }
    });
  }
  for (std::thread& t : pool) t.join();
  for (const std::exception_ptr& e : errors) {
    if (e) std::rethrow_exception(e);
  }
}

// The summary of the outcomes (Section VI's tables).
StudySummary Summarize(const std::vector<BodyOutcome>& bodies) {
  StudySummary s;
  s.bodies = static_cast<int>(bodies.size());
  double sum_negative_eigenvalue = 0.0, sum_triangle = 0.0;
  std::vector<double> lls_errors;
  for (const BodyOutcome& b : bodies) {
    const ConsistencyReport& r = b.linear_ls_report;
    lls_errors.push_back(b.linear_ls_parameter_error);
    s.integrator_steps += b.integrator_steps;
    if (r.fully_consistent()) continue;
    ++s.nonphysical;
    if (!r.mass_positive) ++s.negative_mass;
    if (!r.inertia_positive_definite_origin) {
      ++s.not_positive_definite;
      sum_negative_eigenvalue += r.min_inertia_eigenvalue_origin;
    }
    if (r.mass_positive && !r.inertia_positive_definite_com) ++s.not_positive_definite_com;
    if (r.mass_positive && !r.triangle_inequalities) {
      ++s.triangle_violations;
      sum_triangle += r.min_triangle_margin;
    }
  }
  s.mean_most_negative_eigenvalue = s.not_positive_definite > 0 ? sum_negative_eigenvalue / s.not_positive_definite : 0.0;
  s.mean_triangle_violation = s.triangle_violations > 0 ? sum_triangle / s.triangle_violations : 0.0;
  s.median_linear_ls_parameter_error = Median(lls_errors);
  for (int k = 0; k < kStudyMethods; ++k) {
    MethodSummary& ms = s.methods[k];
    std::vector<double> iterations, errors_k;
    for (const BodyOutcome& b : bodies) {
      const MethodOutcome& m = b.methods[k];
      ms.iterations.push_back(m.iterations);
      iterations.push_back(m.iterations);
      errors_k.push_back(m.parameter_error);
      ms.total_iterations += m.iterations;
      ms.total_seconds += m.seconds;
      if (m.failed) ++ms.failures;
      if (m.reason == StopReason::kMaxIterations) ++ms.max_iteration_stops;
      if (m.reason == StopReason::kNumericalFailure) ++ms.numerical_failures;
      if (!m.consistent) ++ms.inconsistent_results;
      if (m.near_degenerate) ++ms.near_degenerate_results;
      if (m.suboptimal) ++ms.suboptimal_results;
    }
    ms.seconds_per_iteration = ms.total_iterations > 0 ? ms.total_seconds / ms.total_iterations : 0.0;
    ms.median_iterations = Median(iterations);
    ms.median_parameter_error = Median(errors_k);
    double sum = 0.0;
    for (double e : errors_k) sum += e;
    ms.mean_parameter_error = sum / errors_k.size();
  }
  return s;
}

}  // namespace

StudyResult RunStudy(const StudyOptions& options) {
  if (options.bodies < 1) throw std::invalid_argument("study: --bodies must be at least 1");
  if (!(options.duration > 0.0) || !(options.sample_interval > 0.0) ||
      options.sample_interval * 2.0 > options.duration) {
    throw std::invalid_argument("study: duration and sample interval must be positive, with at least 3 samples");
  }
  const auto start = std::chrono::steady_clock::now();
  StudyResult result;
  result.options = options;
  result.bodies.resize(options.bodies);

  const LinearParameterization linear;
  const PositiveEigenvalueParameterization eigenvalue;  // m, L > 0 as Section VI requires
  const ExponentialParameterization exponential;
  const LogCholeskyParameterization log_cholesky;
  const std::array<const Parameterization*, kStudyMethods> parameterizations = {&linear, &eigenvalue, &exponential,
                                                                                 &log_cholesky};
  // The start: spatial inertia = identity (Section VI-B).
  Vector10 pi_start;
  pi_start << 1.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 0.0, 0.0, 0.0;
  std::array<Vector10, kStudyMethods> x_start;
  for (int k = 0; k < kStudyMethods; ++k) {
    if (!parameterizations[k]->FromPi(pi_start, &x_start[k]) ||
        (parameterizations[k]->ToPi(x_start[k]) - pi_start).norm() > 1e-12) {
      throw std::logic_error("study: no start point for " + std::string(StudyMethodName(k)));
    }
  }

  ForEachBodyInParallel(options.bodies, options.threads, [&](int index) {
    StudyBody(options, parameterizations, x_start, index, result.bodies[index]);
  });
  result.summary = Summarize(result.bodies);
  result.summary.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace inertial
