/// @file paper_study.hpp
/// The 1000-body comparison of Rucker & Wensing 2022, Section VI, reproduced.
///
/// For each body: sample the true inertia per Table I with the eigenvalue construction
/// (m ~ U[0.01, 1] kg, c ~ U[-0.5, 0.5]^3 m, L ~ U[0.01, 1]^3 kg m^2, beta uniform in the ball of
/// radius 2 pi, R = exp(S(beta))); start at rest and apply the wrench
/// w_k(t) = sin(t + k pi/3), k = 0..5 (angular first) over t in [0, 2 pi]; integrate eq. (12)
/// (Dormand-Prince 5(4), relative tolerance 1e-10, absolute 1e-12); sample every 0.1 s
/// (t = 0, 0.1, ..., 6.2: 63 samples); add velocity noise uniform on [0.1 - 0.025, 0.1 + 0.025]
/// (width 0.05, mean 0.1) to every twist component; form residuals per eq. (13); then estimate
///  - by linear least squares on pi (the classical method; its consistency is checked), and
///  - by Levenberg-Marquardt (at most 50 iterations) in each of the four parameterizations
///    (linear, eigenvalue, exponential, log-Cholesky), all started from the body whose 6x6 spatial
///    inertia is the identity (m = 1 kg, c = 0, I = 1 kg m^2).
/// A method fails on a body when LM stops without meeting a convergence tolerance (50 iterations
/// reached, or a numerical failure), or, for the three consistent methods, when its final parameters
/// do not give a consistent body by construction (Parameterization::YieldsConsistentBody: possible
/// only for the eigenvalue map, whose m and L are unconstrained).
/// Also counted, not as failures: "near-degenerate" results (consistent by construction, but so thin
/// that the numerical margins round to zero: the constrained optimum of a body whose linear
/// least-squares estimate is nonphysical lies on the boundary of the consistent set, which the
/// iterates approach), and "suboptimal" results (final cost more than 0.1 % above the best cost any
/// consistent method reached on that body).
/// Every body has its own random stream seeded from (seed, body index), so results do not depend on
/// the number of threads.
#pragma once

#include <array>
#include <cstdint>
#include <string_view>
#include <vector>

#include "inertial/estimation/batch/levenberg_marquardt.hpp"
#include "inertial/inertia/consistency.hpp"
#include "inertial/model/rigid_body_simulation.hpp"

namespace inertial {

/// Section VI's choices; every default is the paper's value or stated in the file comment.
struct StudyOptions {
  int bodies = 1000;
  std::uint64_t seed = 1;
  double duration = 6.283185307179586;  ///< 2 pi [s]
  double sample_interval = 0.1;         ///< [s]
  double noise_width = 0.05;            ///< width of the uniform velocity noise
  double noise_bias = 0.1;              ///< its mean
  IntegratorOptions integrator;
  LevenbergMarquardtOptions solver;
  int threads = 0;  ///< 0: one per hardware thread
};

/// Indices of the four methods, in the order of the paper's Fig. 1.
enum StudyMethod : int { kLinear = 0, kEigenvalue = 1, kExponential = 2, kLogCholesky = 3 };
inline constexpr int kStudyMethods = 4;
/// "linear", "eigenvalue", "exponential", "log_cholesky".
std::string_view StudyMethodName(int method);

/// Relative cost excess over the best consistent method that counts a result as suboptimal.
inline constexpr double kSuboptimalRelativeCost = 1e-3;

struct MethodOutcome {
  int iterations = 0;
  StopReason reason = StopReason::kMaxIterations;
  double cost = 0.0;
  Vector10 pi = Vector10::Zero();
  bool consistent = false;       ///< YieldsConsistentBody(final x)
  bool near_degenerate = false;  ///< consistent by construction, numerical margins <= 1e-12 relative
  bool suboptimal = false;       ///< cost > (1 + kSuboptimalRelativeCost) x best consistent cost
  bool failed = false;
  double parameter_error = 0.0;  ///< ||pi - pi_true|| / ||pi_true||
  double seconds = 0.0;          ///< wall time of the fit
};

struct BodyOutcome {
  Vector10 pi_true = Vector10::Zero();
  Vector10 pi_linear_ls = Vector10::Zero();
  ConsistencyReport linear_ls_report;
  double linear_ls_cost = 0.0;
  double linear_ls_parameter_error = 0.0;
  int integrator_steps = 0;
  std::array<MethodOutcome, kStudyMethods> methods;
};

struct MethodSummary {
  std::vector<int> iterations;  ///< one per body
  int failures = 0;
  int max_iteration_stops = 0;
  int numerical_failures = 0;
  int inconsistent_results = 0;
  int near_degenerate_results = 0;
  int suboptimal_results = 0;
  long total_iterations = 0;
  double total_seconds = 0.0;
  double seconds_per_iteration = 0.0;
  double median_iterations = 0.0;
  double median_parameter_error = 0.0;
  double mean_parameter_error = 0.0;
};

struct StudySummary {
  int bodies = 0;
  // Linear least squares (the paper: 151 nonphysical, 42 with I not positive definite, mean most
  // negative eigenvalue -0.04 kg m^2, all 151 violating a triangle inequality, mean violation
  // -0.09 kg m^2, no negative mass).
  int nonphysical = 0;
  int negative_mass = 0;
  int not_positive_definite = 0;      ///< rotational inertia about the frame origin (the paper's I-bar)
  int not_positive_definite_com = 0;  ///< rotational inertia about the COM
  int triangle_violations = 0;        ///< at the COM
  double mean_most_negative_eigenvalue = 0.0;  ///< over the not_positive_definite cases [kg m^2]
  double mean_triangle_violation = 0.0;        ///< over the triangle_violations cases [kg m^2]
  double median_linear_ls_parameter_error = 0.0;
  std::array<MethodSummary, kStudyMethods> methods;
  double wall_seconds = 0.0;
  long integrator_steps = 0;
};

struct StudyResult {
  StudyOptions options;
  std::vector<BodyOutcome> bodies;
  StudySummary summary;
};

/// Samples one true body per Table I from the body's own generator.
InertialParams SampleTableIBody(std::uint64_t seed, int body_index);

/// The study's wrench w(t) (Section VI-A).
Vector6 StudyWrench(double t);

/// Simulated, noisy measurements of one body (samples every sample_interval from 0 to duration).
std::vector<TwistWrenchSample> SimulateStudyBody(const InertialParams& body, std::uint64_t seed, int body_index,
                                                 const StudyOptions& options, int* integrator_steps = nullptr);

/// Runs every body (in parallel) and summarizes.
/// @throws std::invalid_argument if options.bodies < 1 or a time setting is not positive.
StudyResult RunStudy(const StudyOptions& options);

}  // namespace inertial
