/// @file levenberg_marquardt.hpp
/// Nonlinear least squares over any Parameterization: minimize F(x) = 0.5 ||A pi(x) - b||^2 by
/// Levenberg-Marquardt (Gauss-Newton with adaptive damping). The Jacobian of the residual is
/// A J_pi_x, exact because every Parameterization returns an exact J_pi_x.
///
/// Damping: (H + lambda D) dx = -g with H = J^T J, g = J^T r, D = diag(H) floored at 1e-12 max(diag H)
/// (Marquardt's scaling, so units of x do not matter); lambda follows Nielsen's (1999) gain-ratio
/// rule. An iteration is one Jacobian evaluation followed by trial steps until one lowers F.
///
/// Stopping (the paper caps at 50 iterations, Section VI-B; tolerances like Matlab lsqnonlin's
/// defaults):
///  - kGradient: ||g||_inf <= gradient_tolerance * max(1, ||g(x0)||_inf);
///  - kStep: ||dx|| <= step_tolerance * (step_tolerance + ||x||);
///  - kFunction: an accepted step lowered F by at most function_tolerance * F;
///  - kMaxIterations: the iteration cap was reached first (not converged);
///  - kNumericalFailure: F or the Jacobian became non-finite, or damping exceeded 1e16.
#pragma once

#include <functional>

#include <string_view>

#include "inertial/inertia/parameterization.hpp"
#include "inertial/model/midpoint_regression.hpp"

namespace inertial {

struct LevenbergMarquardtOptions {
  int max_iterations = 50;
  double function_tolerance = 1e-6;
  double step_tolerance = 1e-6;
  double gradient_tolerance = 1e-6;
  double initial_damping = 1e-3;
  /// Damping matrix D: Marquardt's diag(H) (true) or Levenberg's max(diag H) times the identity
  /// (false; only MinimizeLevenbergMarquardt of dense_levenberg_marquardt.hpp reads it). Levenberg's
  /// form lets the steps follow directions of small curvature that have large diagonal entries.
  bool scaled_damping = true;
  /// Optional: called at the start of each iteration with its number and the cost so far.
  std::function<void(int iteration, double cost)> progress;
};

enum class StopReason { kGradient, kStep, kFunction, kMaxIterations, kNumericalFailure };

/// "gradient", "step", "function", "max_iterations", "numerical_failure".
std::string_view ToString(StopReason reason);

struct LevenbergMarquardtResult {
  Vector10 x = Vector10::Zero();   ///< final parameters
  Vector10 pi = Vector10::Zero();  ///< pi(x)
  double initial_cost = 0.0;
  double cost = 0.0;               ///< final 0.5 ||A pi - b||^2
  int iterations = 0;              ///< Jacobian evaluations
  int cost_evaluations = 0;
  StopReason reason = StopReason::kMaxIterations;
  bool converged() const { return reason != StopReason::kMaxIterations && reason != StopReason::kNumericalFailure; }
};

/// Fits from x0. Allocates its workspace once per call (sized by A).
/// @throws std::invalid_argument if A, b have inconsistent sizes or x0 is not finite.
LevenbergMarquardtResult FitLevenbergMarquardt(const Parameterization& parameterization,
                                               const LinearRegression& regression, const Vector10& x0,
                                               const LevenbergMarquardtOptions& options = LevenbergMarquardtOptions());

}  // namespace inertial
