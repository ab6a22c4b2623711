/// @file region_barrier.hpp
/// What keeps every fitted body inside its region (EstimatedBody::region, body_region.hpp), with
/// the fit still unconstrained in log-Cholesky theta: a smooth barrier added to eq. 14's cost,
///
///   b(theta) = phi(s(theta)) + phi(1 - m(theta) / m_max),   s = tr(Q J(theta)) / m  (slack, in (0, 1]),
///   phi(s) = -log(s / s0) + (s / s0 - 1) - (s / s0 - 1)^2 / 2  for s < s0,  0 for s >= s0,
///
/// +infinity outside (s <= 0 or m >= m_max). phi is a log barrier made one-sided: its value, slope and
/// curvature vanish at s0 = kBarrierOnset (C^2), so a body with slack above s0 feels nothing and
/// its fit is exactly eq. 14's (no bias inside the region: a uniform solid ellipsoid filling its
/// region has s = 0.4, a body whose mass keeps a tenth of the region's normalized squared radius
/// free has s = 0.1), and one the data push toward the boundary meets a wall that rises to infinity
/// at it. Levenberg-Marquardt rejects a step whose cost is not
/// finite (dense_levenberg_marquardt.hpp), and the fit starts at the priors, which every region
/// holds strictly; so every iterate, not only the result, is a body inside its region. The
/// identification minimizes 0.5 (||A w - tau||^2 + gamma sum d_b + mu sum b_b).
///
/// Why a barrier, not a reparameterization. The region's condition tr(Q J) >= 0 is one linear
/// inequality on J with Q indefinite (one positive, three negative eigenvalues); no smooth
/// one-to-one map of R^10 onto {J > 0, tr(Q J) >= 0} is known in closed form, and a squashing map
/// (e.g. of the slack through a sigmoid) would flatten the cost near the boundary, where a body the
/// data push against its region must stay well conditioned. The barrier keeps theta, its Jacobian
/// and the divergence prior exactly as they are, adds one smooth term per body, and is exactly zero away from the boundary.
///
/// Weight. mu = kRegionBarrierWeight * tau^T tau / N (RegionBarrierWeight): the barrier weighs as
/// much as 1/20 of one sample's squared torque, so it is scale-free (a robot in N m or in kN m, a
/// log of any length) and negligible against the thousands of samples of a log while a body is well
/// inside its region (s ~ 0.3-0.6), and where the data push a body outward it stops at a small
/// positive slack. A weight in the cost's absolute units cannot do both: at the paper's gamma = 1e-2
/// on the leg (a mean squared torque of 16 N^2 m^2 per sample) a body pushed outward crept along
/// its boundary (slack 1e-10) and Levenberg-Marquardt stopped after 1000 iterations at 7 times the
/// constrained optimum's cost; at 1/20 of a sample it converged in 200 iterations to slack 0.02.
/// Derivatives in pi: with a = q . pi (q = RegionCoefficients), m = pi_0, s = a / m, r = 1 - m / m_max,
///   ds/dpi = (q - s e_0) / m,  d2s/dpi2 = -(q e_0^T + e_0 q^T) / m^2 + 2 a e_0 e_0^T / m^3,  dr/dpi = -e_0 / m_max,
///   db/dpi = phi'(s) ds/dpi + phi'(r) dr/dpi,
///   d2b/dpi2 = phi''(s) ds ds^T + phi'(s) d2s/dpi2 + phi''(r) dr dr^T   (phi'' >= 0 below s0);
/// in theta through J = dpi/dtheta: J^T db/dpi, and J^T d2b/dpi2 J + sum_k (db/dpi)_k d2pi_k/dtheta2
/// (LogCholeskyParameterization::ContractedHessian) when `newton`; without it (Gauss-Newton) the
/// positive semi-definite part J^T (phi''(s) ds ds^T + phi''(r) dr dr^T) J.
#pragma once

#include <vector>

#include "inertial/model/robot_dynamics.hpp"

namespace inertial {

/// s0 of phi (file comment): the barrier acts on a body whose slack falls below it
/// (body_region.hpp's kWellInsideSlack).
inline constexpr double kBarrierOnset = kWellInsideSlack;

/// mu's share of one sample's squared torque (file comment).
inline constexpr double kRegionBarrierWeight = 0.05;

/// phi of the file comment with onset s0 (> 0) in place of kBarrierOnset, with its first and second
/// derivative: zero at and above s0, +infinity at and below 0. Below s0, phi' = -(1/s)(1 - s/s0)^2 <= 0
/// and phi'' = 1/s^2 - 1/s0^2 >= 0. Shared with the total-mass barrier (total_mass_barrier.hpp).
struct OneSidedLog {
  double value = 0.0, first = 0.0, second = 0.0;
};
OneSidedLog OneSidedLogBarrier(double s, double s0);

/// mu = kRegionBarrierWeight * btb / num_samples of the statistics the fit minimizes over (a tiny
/// positive floor without data).
double RegionBarrierWeight(double btb, int num_samples);

/// b(theta) of body `body` (its region must be set); its gradient and curvature (file comment) into
/// g and H when not null. +infinity (g, H untouched) outside the region or where theta overflows.
double RegionBarrier(const EstimatedBody& body, const Vector10& theta, bool newton, Vector10* g = nullptr,
                     Matrix10* H = nullptr);

/// The barrier term of a whole fit: mu * sum_b b_b(theta_b) over the bodies of x that have a region
/// and are not frozen (frozen_bodies empty: none is), with 0.5 mu times its gradient and curvature
/// added to g and H (the fit's cost is 0.5 (... + mu sum b)) when they are not null. Returns the sum
/// sum_b b_b unweighted, or +infinity (g, H partly updated) if a body is outside its region.
double AddRegionBarriers(const RobotDynamics& model, const Eigen::VectorXd& x, double mu, bool newton,
                         const std::vector<bool>& frozen_bodies, Eigen::VectorXd* g, Eigen::MatrixXd* H);

/// The region's slack s = tr(Q J) / m of body `body` at theta (1 - its mass's mean normalized
/// squared distance from the region's centre), or +infinity if it has no region.
double RegionSlack(const EstimatedBody& body, const Vector10& theta);

}  // namespace inertial
