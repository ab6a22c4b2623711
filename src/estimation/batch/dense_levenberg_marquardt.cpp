#include "inertial/estimation/batch/dense_levenberg_marquardt.hpp"

#include "inertial/estimation/batch/smallest_eigenvalue.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace inertial {

DenseLevenbergMarquardtResult MinimizeLevenbergMarquardt(const NormalEquationsFn& problem, const Eigen::VectorXd& x0,
                                                         const LevenbergMarquardtOptions& options) {
  if (!x0.allFinite()) throw std::invalid_argument("Levenberg-Marquardt: initial parameters are not finite");
  DenseLevenbergMarquardtResult result;
  Eigen::VectorXd x = x0, g;
  Eigen::MatrixXd H;
  double F = 0.0;
  auto finish = [&](StopReason reason) {
    result.x = x;
    result.cost = F;
    result.reason = reason;
    return result;
  };
  if (!problem(x, &F, &g, &H) || !std::isfinite(F)) return finish(StopReason::kNumericalFailure);
  result.initial_cost = F;
  result.cost_history.push_back(F);
  double lambda = options.initial_damping, nu = 2.0;
  const double g0_norm = g.lpNorm<Eigen::Infinity>();
  for (int iteration = 1; iteration <= options.max_iterations; ++iteration) {
    result.iterations = iteration;
    if (options.progress) options.progress(iteration, F);
    if (!g.allFinite() || !H.allFinite()) return finish(StopReason::kNumericalFailure);
    if (g.lpNorm<Eigen::Infinity>() <= options.gradient_tolerance * std::max(1.0, g0_norm)) {
      return finish(StopReason::kGradient);
    }
    const Eigen::VectorXd abs_diag = H.diagonal().cwiseAbs();
    const double max_diag = std::max(abs_diag.maxCoeff(), 1e-300);
    const Eigen::VectorXd diag = options.scaled_damping ? Eigen::VectorXd(abs_diag.cwiseMax(1e-12 * max_diag))
                                                        : Eigen::VectorXd::Constant(H.rows(), max_diag);
    while (true) {
      Eigen::MatrixXd damped = H;
      damped.diagonal() += lambda * diag;
      // H may be indefinite (a Newton Hessian): only a positive definite damped matrix gives a
      // descent step; otherwise damp more.
      const Eigen::LLT<Eigen::MatrixXd> llt(damped);
      if (llt.info() != Eigen::Success) {
        // Just enough damping to make it positive definite: lambda above minus the smallest
        // eigenvalue of D^-1/2 H D^-1/2 (one eigen-decomposition), without the escalation of a
        // rejected step (which would leave lambda far too large for the next iterations).
        const Eigen::VectorXd s = diag.cwiseSqrt().cwiseInverse();
        const Eigen::MatrixXd scaled = s.asDiagonal() * H * s.asDiagonal();
        // From below, within 0.1 %: the damping may exceed the minimum by that much, never fall short.
        const double min_eigenvalue = SmallestEigenvalue(scaled, 1e-3);
        const double needed = -min_eigenvalue * 1.01 + 1e-12;
        lambda = std::max(2.0 * lambda, needed);
        if (!(lambda <= 1e16)) return finish(StopReason::kNumericalFailure);
        continue;
      }
      const Eigen::VectorXd dx = llt.solve(-g);
      if (!dx.allFinite()) return finish(StopReason::kNumericalFailure);
      if (dx.norm() <= options.step_tolerance * (options.step_tolerance + x.norm())) return finish(StopReason::kStep);
      const Eigen::VectorXd x_trial = x + dx;
      double F_trial = 0.0;
      const bool ok = problem(x_trial, &F_trial, nullptr, nullptr) && std::isfinite(F_trial);
      const double predicted = 0.5 * dx.dot(lambda * diag.cwiseProduct(dx) - g);
      const double actual = F - F_trial;
      if (ok && actual > 0.0) {
        const double rho = predicted > 0.0 ? actual / predicted : 1.0;
        lambda *= std::max(1.0 / 3.0, 1.0 - std::pow(2.0 * rho - 1.0, 3));
        nu = 2.0;
        const double F_old = F;
        x = x_trial;
        if (!problem(x, &F, &g, &H)) return finish(StopReason::kNumericalFailure);
        result.cost_history.push_back(F);
        if (actual <= options.function_tolerance * F_old) return finish(StopReason::kFunction);
        break;
      }
      lambda *= nu;
      nu *= 2.0;
      if (lambda > 1e16) return finish(StopReason::kNumericalFailure);
    }
  }
  return finish(StopReason::kMaxIterations);
}

}  // namespace inertial
