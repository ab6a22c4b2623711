/// @file dense_levenberg_marquardt.hpp
/// Levenberg-Marquardt for a least-squares problem given by its Gauss-Newton normal equations:
/// the caller evaluates F(x) = 0.5 ||r(x)||^2, g = J^T r and H = J^T J (or the exact Hessian of F,
/// which may be indefinite: a damped matrix that is not positive definite is damped further) at x
/// (for problems where
/// J^T J is cheaper to form than J, e.g. when the data enter only through A^T A).
/// Damping, steps and stopping rules are those of levenberg_marquardt.hpp (Marquardt or Levenberg
/// scaling, Nielsen's gain-ratio update), with any number of parameters.
#pragma once

#include <functional>
#include <vector>

#include <Eigen/Core>

#include "inertial/estimation/batch/levenberg_marquardt.hpp"

namespace inertial {

/// Evaluates F at x; when g and H are not null, also the gradient and the Gauss-Newton matrix
/// (or the exact Hessian).
/// Returns false if F (or g, H) could not be computed (non-finite).
using NormalEquationsFn = std::function<bool(const Eigen::VectorXd& x, double* F, Eigen::VectorXd* g, Eigen::MatrixXd* H)>;

struct DenseLevenbergMarquardtResult {
  Eigen::VectorXd x;
  double initial_cost = 0.0;
  double cost = 0.0;
  int iterations = 0;
  StopReason reason = StopReason::kMaxIterations;
  std::vector<double> cost_history;  ///< F after each iteration, starting with F(x0)
  bool converged() const { return reason != StopReason::kMaxIterations && reason != StopReason::kNumericalFailure; }
};

/// @throws std::invalid_argument if x0 is not finite.
DenseLevenbergMarquardtResult MinimizeLevenbergMarquardt(const NormalEquationsFn& problem, const Eigen::VectorXd& x0,
                                                         const LevenbergMarquardtOptions& options);

}  // namespace inertial
