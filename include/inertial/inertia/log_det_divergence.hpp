/// @file log_det_divergence.hpp
/// The coordinate-invariant regularizer of the paper's eq. (14) (Lee & Wensing 2019, ref. [10]):
/// the log-det (Bregman) divergence between the pseudo-inertia J of an estimate and the prior's J0,
///
///   d(J || J0) = tr(J0^-1 J) - log det(J0^-1 J) - 4,
///
/// written as a sum of squares so that Gauss-Newton and Levenberg-Marquardt can use it.
///
/// With theta relative to the prior (eq. 11), J = U J0 U^T and J0 = U0 U0^T, so J0^-1 J is similar
/// to W W^T with W = U0^-1 U U0, upper triangular with the same diagonal as U. Hence
///
///   d = sum_i (w_ii^2 - 2 log w_ii - 1) + sum_{i<j} w_ij^2,
///
/// and with x_i = log w_ii (x = alpha + d_1, alpha + d_2, alpha + d_3, alpha) every term is a
/// square: w_ii^2 - 2 log w_ii - 1 = f(x_i)^2 with f(x) = sign(x) sqrt(e^{2x} - 2x - 1), which is
/// smooth (f(x) = sqrt(2) x (1 + x/3 + ...) near 0). The ten residuals are
///   r = [f(x_1), f(x_2), f(x_3), f(x_4), w_01, w_02, w_03, w_12, w_13, w_23],  d = ||r||^2.
/// d is zero exactly at the prior, non-negative, and unchanged when estimate and prior are moved by
/// the same rigid or affine change of coordinates.
#pragma once

#include "inertial/inertia/log_cholesky.hpp"

namespace inertial {

/// Residuals r(theta) with ||r||^2 = d(J(theta) || J0) for the log-Cholesky map relative to the prior
/// J0 (eq. 11); J_r_theta (optional) is the exact 10x10 Jacobian. Never allocates, never throws.
Vector10 LogDetDivergenceResiduals(const LogCholeskyParameterization& map, const Vector10& theta,
                                   Matrix10* J_r_theta = nullptr);

/// d(J || J0) = tr(J0^-1 J) - log det(J0^-1 J) - 4 computed directly from two pseudo-inertias
/// (for reports and tests). Both must be positive definite.
double LogDetDivergence(const Matrix4& J, const Matrix4& J0);

}  // namespace inertial
