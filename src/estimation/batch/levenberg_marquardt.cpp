#include "inertial/estimation/batch/levenberg_marquardt.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace inertial {

std::string_view ToString(StopReason reason) {
  switch (reason) {
    case StopReason::kGradient: return "gradient";
    case StopReason::kStep: return "step";
    case StopReason::kFunction: return "function";
    case StopReason::kMaxIterations: return "max_iterations";
    case StopReason::kNumericalFailure: return "numerical_failure";
  }
  return "unknown";
}

LevenbergMarquardtResult FitLevenbergMarquardt(const Parameterization& parameterization,
                                               const LinearRegression& regression, const Vector10& x0,
                                               const LevenbergMarquardtOptions& options) {
  const Eigen::MatrixXd& A = regression.A;
  const Eigen::VectorXd& b = regression.b;
  if (A.cols() != 10 || A.rows() != b.rows()) {
    throw std::invalid_argument("Levenberg-Marquardt: A must be N x 10 and b of length N");
  }
  if (!x0.allFinite()) throw std::invalid_argument("Levenberg-Marquardt: initial parameters are not finite");

  LevenbergMarquardtResult result;
  Eigen::VectorXd r(A.rows());
  Eigen::MatrixXd JA(A.rows(), 10);
  Matrix10 J_pi_x;
  auto cost_at = [&](const Vector10& x, Vector10* pi) {
    *pi = parameterization.ToPi(x);
    ++result.cost_evaluations;
    r.noalias() = A * *pi;
    r -= b;
    return 0.5 * r.squaredNorm();
  };

  Vector10 x = x0;
  Vector10 pi;
  double F = cost_at(x, &pi);
  result.initial_cost = F;
  double lambda = options.initial_damping;
  double nu = 2.0;
  double g0_norm = -1.0;
  result.reason = StopReason::kMaxIterations;

  auto finish = [&](StopReason reason) {
    result.x = x;
    result.pi = parameterization.ToPi(x);
    result.cost = F;
    result.reason = reason;
    return result;
  };
  if (!std::isfinite(F)) return finish(StopReason::kNumericalFailure);

  for (int iteration = 1; iteration <= options.max_iterations; ++iteration) {
    result.iterations = iteration;
    // Residual r at x is current (cost_at was last called at x, or re-evaluated below).
    parameterization.ToPi(x, &J_pi_x);
    JA.noalias() = A * J_pi_x;
    const Matrix10 H = JA.transpose() * JA;
    const Vector10 g = JA.transpose() * r;
    if (!H.allFinite() || !g.allFinite()) return finish(StopReason::kNumericalFailure);
    const double g_norm = g.lpNorm<Eigen::Infinity>();
    if (g0_norm < 0.0) g0_norm = g_norm;
    if (g_norm <= options.gradient_tolerance * std::max(1.0, g0_norm)) return finish(StopReason::kGradient);

    const Vector10 diag = H.diagonal().cwiseMax(1e-12 * std::max(H.diagonal().maxCoeff(), 1e-300));
    while (true) {
      Matrix10 damped = H;
      damped.diagonal() += lambda * diag;
      const Vector10 dx = damped.ldlt().solve(-g);
      if (!dx.allFinite()) return finish(StopReason::kNumericalFailure);
      if (dx.norm() <= options.step_tolerance * (options.step_tolerance + x.norm())) {
        return finish(StopReason::kStep);
      }
      const Vector10 x_trial = x + dx;
      Vector10 pi_trial;
      const double F_trial = cost_at(x_trial, &pi_trial);
      // Predicted decrease of the damped Gauss-Newton model: -g.dx - 0.5 dx.H.dx = 0.5 dx.(lambda D dx - g).
      const double predicted = 0.5 * dx.dot(lambda * diag.cwiseProduct(dx) - g);
      const double actual = F - F_trial;
      if (std::isfinite(F_trial) && actual > 0.0) {
        const double rho = predicted > 0.0 ? actual / predicted : 1.0;
        lambda *= std::max(1.0 / 3.0, 1.0 - std::pow(2.0 * rho - 1.0, 3));
        nu = 2.0;
        const double F_old = F;
        x = x_trial;
        pi = pi_trial;
        F = F_trial;  // r now holds the residual at the new x
        if (actual <= options.function_tolerance * F_old) return finish(StopReason::kFunction);
        break;
      }
      lambda *= nu;
      nu *= 2.0;
      if (lambda > 1e16) {
        cost_at(x, &pi);  // restore r at x
        return finish(StopReason::kNumericalFailure);
      }
    }
  }
  return finish(StopReason::kMaxIterations);
}

}  // namespace inertial
