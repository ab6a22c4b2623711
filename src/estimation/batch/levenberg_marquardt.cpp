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

namespace {

// The iterate of the Levenberg-Marquardt loop: the parameters x, their pi, the cost F at x, and the
// damping lambda with its growth factor nu.
struct LmState {
  Vector10 x;
  Vector10 pi;
  double F = 0.0;
  double lambda = 0.0;
  double nu = 2.0;
};

// Tries damped Gauss-Newton steps from s.x, raising the damping until the cost decreases, and takes
// the first that does. Returns true, with *reason, when the fit stops here (a step too small, a
// decrease below the function tolerance, a numerical failure); false when a step was taken and the
// iterations go on. cost_at(x, &pi) evaluates the cost and leaves the residual at x.
template <typename CostAt>
bool TakeDampedStep(const Matrix10& H, const Vector10& g, const LevenbergMarquardtOptions& options, CostAt& cost_at,
                    LmState& s, StopReason* reason) {
  const Vector10 diag = H.diagonal().cwiseMax(1e-12 * std::max(H.diagonal().maxCoeff(), 1e-300));
  while (true) {
    Matrix10 damped = H;
    damped.diagonal() += s.lambda * diag;
    const Vector10 dx = damped.ldlt().solve(-g);
    if (!dx.allFinite()) {
      *reason = StopReason::kNumericalFailure;
      return true;
    }
    if (dx.norm() <= options.step_tolerance * (options.step_tolerance + s.x.norm())) {
      *reason = StopReason::kStep;
      return true;
    }
    const Vector10 x_trial = s.x + dx;
    Vector10 pi_trial;
    const double F_trial = cost_at(x_trial, &pi_trial);
    // Predicted decrease of the damped Gauss-Newton model: -g.dx - 0.5 dx.H.dx = 0.5 dx.(lambda D dx - g).
    const double predicted = 0.5 * dx.dot(s.lambda * diag.cwiseProduct(dx) - g);
    const double actual = s.F - F_trial;
    if (std::isfinite(F_trial) && actual > 0.0) {
      const double rho = predicted > 0.0 ? actual / predicted : 1.0;
      s.lambda *= std::max(1.0 / 3.0, 1.0 - std::pow(2.0 * rho - 1.0, 3));
      s.nu = 2.0;
      const double F_old = s.F;
      s.x = x_trial;
      s.pi = pi_trial;
      s.F = F_trial;  // r now holds the residual at the new x
      if (actual <= options.function_tolerance * F_old) {
        *reason = StopReason::kFunction;
        return true;
      }
      return false;
    }
    s.lambda *= s.nu;
    s.nu *= 2.0;
    if (s.lambda > 1e16) {
      cost_at(s.x, &s.pi);  // restore r at x
      *reason = StopReason::kNumericalFailure;
      return true;
    }
  }
}

}  // namespace

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

  LmState s;
  s.x = x0;
  s.F = cost_at(s.x, &s.pi);
  result.initial_cost = s.F;
  s.lambda = options.initial_damping;
  s.nu = 2.0;
  double g0_norm = -1.0;
  result.reason = StopReason::kMaxIterations;

  auto finish = [&](StopReason reason) {
    result.x = s.x;
    result.pi = parameterization.ToPi(s.x);
    result.cost = s.F;
    result.reason = reason;
    return result;
  };
  if (!std::isfinite(s.F)) return finish(StopReason::kNumericalFailure);

  for (int iteration = 1; iteration <= options.max_iterations; ++iteration) {
    result.iterations = iteration;
    // Residual r at x is current (cost_at was last called at x, or re-evaluated below).
    parameterization.ToPi(s.x, &J_pi_x);
    JA.noalias() = A * J_pi_x;
    const Matrix10 H = JA.transpose() * JA;
    const Vector10 g = JA.transpose() * r;
    if (!H.allFinite() || !g.allFinite()) return finish(StopReason::kNumericalFailure);
    const double g_norm = g.lpNorm<Eigen::Infinity>();
    if (g0_norm < 0.0) g0_norm = g_norm;
    if (g_norm <= options.gradient_tolerance * std::max(1.0, g0_norm)) return finish(StopReason::kGradient);
    StopReason reason = StopReason::kMaxIterations;
    if (TakeDampedStep(H, g, options, cost_at, s, &reason)) return finish(reason);
  }
  return finish(StopReason::kMaxIterations);
}

}  // namespace inertial
