#include "inertial/inertia/log_det_divergence.hpp"

#include <Eigen/Cholesky>
#include <cmath>

namespace inertial {
namespace {

// f(x) = sign(x) sqrt(e^{2x} - 2x - 1) and f'(x). Near zero, f = x sqrt(h(x)) with
// h(x) = (e^{2x} - 2x - 1) / x^2 = sum_{k>=2} 2^k x^{k-2} / k!, summed as a series to avoid cancellation.
void DiagonalResidual(double x, double* f, double* df) {
  if (std::abs(x) < 1e-2) {
    // h = 2 + 4x/3 + 2x^2/3 + 4x^3/15 + 4x^4/45 + 8x^5/315 (next term below 1e-14 relative).
    const double h = 2.0 + x * (4.0 / 3.0 + x * (2.0 / 3.0 + x * (4.0 / 15.0 + x * (4.0 / 45.0 + x * (8.0 / 315.0)))));
    const double dh = 4.0 / 3.0 + x * (4.0 / 3.0 + x * (12.0 / 15.0 + x * (16.0 / 45.0 + x * (40.0 / 315.0))));
    const double s = std::sqrt(h);
    *f = x * s;
    *df = s + x * dh / (2.0 * s);
    return;
  }
  const double g = std::expm1(2.0 * x) - 2.0 * x;
  *f = std::copysign(std::sqrt(g), x);
  *df = std::expm1(2.0 * x) / *f;
}

}  // namespace

Vector10 LogDetDivergenceResiduals(const LogCholeskyParameterization& map, const Vector10& theta, Matrix10* J_r_theta) {
  using namespace theta_index;
  const Matrix4 U = LogCholeskyFactor(theta);
  Matrix4 U0;
  if (!UpperCholesky(map.reference_pseudo_inertia(), &U0)) U0.setIdentity();  // cannot happen: J0 is PD
  const Matrix4 U0_inv = U0.triangularView<Eigen::Upper>().solve(Matrix4::Identity());
  const Matrix4 W = U0_inv * U * U0;

  const double x[4] = {theta[kAlpha] + theta[kD1], theta[kAlpha] + theta[kD2], theta[kAlpha] + theta[kD3],
                       theta[kAlpha]};
  double df[4];
  Vector10 r;
  for (int i = 0; i < 4; ++i) DiagonalResidual(x[i], &r[i], &df[i]);
  static constexpr int kRow[6] = {0, 0, 0, 1, 1, 2};
  static constexpr int kCol[6] = {1, 2, 3, 2, 3, 3};
  for (int k = 0; k < 6; ++k) r[4 + k] = W(kRow[k], kCol[k]);

  if (J_r_theta != nullptr) {
    J_r_theta->setZero();
    // Diagonal residuals: x_i depends on alpha and d_i only.
    for (int i = 0; i < 4; ++i) (*J_r_theta)(i, kAlpha) = df[i];
    (*J_r_theta)(0, kD1) = df[0];
    (*J_r_theta)(1, kD2) = df[1];
    (*J_r_theta)(2, kD3) = df[2];
    // Off-diagonal residuals: dW = U0^-1 dU U0 with dU from eq. (8).
    const double e = std::exp(theta[kAlpha]);
    for (int p = 0; p < 10; ++p) {
      Matrix4 dU = Matrix4::Zero();
      switch (p) {
        case kAlpha: dU = U; break;
        case kD1: dU(0, 0) = U(0, 0); break;
        case kD2: dU(1, 1) = U(1, 1); break;
        case kD3: dU(2, 2) = U(2, 2); break;
        case kS12: dU(0, 1) = e; break;
        case kS23: dU(1, 2) = e; break;
        case kS13: dU(0, 2) = e; break;
        case kT1: dU(0, 3) = e; break;
        case kT2: dU(1, 3) = e; break;
        case kT3: dU(2, 3) = e; break;
        default: break;
      }
      const Matrix4 dW = U0_inv * dU * U0;
      for (int k = 0; k < 6; ++k) (*J_r_theta)(4 + k, p) = dW(kRow[k], kCol[k]);
    }
  }
  return r;
}

double LogDetDivergence(const Matrix4& J, const Matrix4& J0) {
  const Eigen::LLT<Matrix4> llt(J0);
  const Matrix4 M = llt.solve(J);
  const double log_det = 2.0 * Eigen::LLT<Matrix4>(J).matrixL().toDenseMatrix().diagonal().array().log().sum() -
                         2.0 * llt.matrixL().toDenseMatrix().diagonal().array().log().sum();
  return M.trace() - log_det - 4.0;
}

}  // namespace inertial
