/// @file total_mass_barrier.hpp
/// The robot's total mass as weighed, M, as a bound a fit keeps: the links' masses may not add up
/// to more than the robot weighs. With the parts of the robot no estimated body holds (the links
/// fixed to the base, F, at their URDF masses) and the links of the model (every tree body but the
/// rotors: estimated ones and frozen ones alike; payloads are not part of the robot and rotors are
/// inside their links' masses in a URDF),
///
///   M_fit(x) = F + sum_links m_e,   m_e = e^{2 alpha_e} m_prior,e   (alpha_e = x[10 e]),
///
/// the last because the log-Cholesky factor's last row is e^alpha [0 0 0 1] (log_cholesky.hpp), so
/// (U J0 U^T)_33 = e^{2 alpha} (J0)_33 whatever the other entries of theta: a link's mass depends on
/// its alpha alone. The fit's cost gets, like each body's region (region_barrier.hpp),
///
///   b(x) = phi(r),   r = 1 - M_fit(x) / M,   phi = OneSidedLogBarrier( . , kTotalMassOnset),
///
/// zero while M_fit <= (1 - r0) M (r0 = kTotalMassOnset), C^2 at the onset, +infinity at M_fit = M:
/// Levenberg-Marquardt rejects a step beyond the bound, so no iterate exceeds it. The weight is the
/// region barrier's mu (RegionBarrierWeight): one more term of the same kind.
///
/// Derivatives (only the links' alphas enter), with dr/dalpha_e = -2 m_e / M and
/// d2r/dalpha_e2 = -4 m_e / M (no cross terms):
///   db/dalpha_e = -2 phi'(r) m_e / M,
///   d2b/dalpha_e dalpha_f = phi''(r) (2 m_e / M)(2 m_f / M) - 4 phi'(r) (m_e / M) delta_ef   (Newton),
///   Gauss-Newton: the first term alone, phi''(r) dr dr^T.
/// Below the onset phi' <= 0 and phi'' >= 0 (region_barrier.hpp), so both are positive
/// semi-definite.
///
/// The onset r0 = 0.05: the bound itself is uncertain by a few per cent of M. A scale weighs a
/// robot to about 1 %, and F carries the URDF's error of the links fixed to the base (a CAD mass is
/// off by tens of per cent of its own: a base of a tenth of the robot drawn 30 % light or heavy
/// moves M - F by 3 % of M). A fit whose total is more than 5 % below M is therefore one the
/// weighing cannot dispute, and it is fitted exactly as without the bound (the barrier is exactly
/// zero there; tested to the last digit). Within the last 5 % the wall rises; its pull on a fit the
/// data determine is negligible (mu is 1/20 of one sample's squared torque against the thousands of
/// samples the data term sums), so what it moves is what the data do not determine: a link whose
/// mass the data let grow (a payload or friction not in the model explained with mass).
///
/// Conventions: SI units (kg).
#pragma once

#include <vector>

#include "inertial/model/robot_dynamics.hpp"

namespace inertial {

/// The onset r0 of the file comment (a fraction of M).
inline constexpr double kTotalMassOnset = 0.05;

struct TotalMassBound {
  double total = 0.0;  ///< M [kg]: the whole robot as weighed (> 0)
  double fixed = 0.0;  ///< F [kg]: the robot's mass no body of the model holds (links fixed to the base), >= 0
};

/// Whether estimated body e is a link (counted in M_fit): a tree body that is not a rotor.
bool IsRobotLink(const RobotDynamics& model, int e);

/// sum over the link bodies of m_e at x (file comment), without F [kg].
double LinkMassSum(const RobotDynamics& model, const Eigen::VectorXd& x);

/// b(x) of the file comment, unweighted; its gradient (size num_parameters) and curvature (square,
/// num_parameters; Newton's with `newton`, else Gauss-Newton's) written into g and H when not null
/// (zero outside the links' alphas). +infinity (g, H untouched) at or beyond the bound.
/// @throws std::invalid_argument if the bound is not positive and finite, F negative or not finite,
/// or x has the wrong size.
double TotalMassBarrier(const RobotDynamics& model, const TotalMassBound& bound, const Eigen::VectorXd& x, bool newton,
                        Eigen::VectorXd* g = nullptr, Eigen::MatrixXd* H = nullptr);

/// The term of a whole fit, as AddRegionBarriers: adds 0.5 mu times b's gradient and curvature to g
/// and H (when both are not null; entries of frozen bodies left alone) and returns b unweighted
/// (+infinity at or beyond the bound, g and H then untouched).
double AddTotalMassBarrier(const RobotDynamics& model, const TotalMassBound& bound, const Eigen::VectorXd& x, double mu,
                           bool newton, const std::vector<bool>& frozen_bodies, Eigen::VectorXd* g, Eigen::MatrixXd* H);

/// A start inside the bound: x itself if M_fit(x) < M; otherwise x with the alpha of every link
/// whose mass may move (`movable`, one flag per estimated body; empty: every link) raised by one
/// common log-factor, so that the total is (1 - kTotalMassOnset) M: the priors' mass ratios kept,
/// their sum brought to where the barrier begins. Scaling a body's mass this way scales its whole
/// pseudo-inertia, so its slack in its region is unchanged and its mass only falls: a start inside
/// its region stays inside.
/// @throws std::invalid_argument naming the masses if the links that may not move and F already
/// weigh (1 - kTotalMassOnset) M or more (or no link may move while the total exceeds M).
Eigen::VectorXd IntoTotalMassBound(const RobotDynamics& model, const TotalMassBound& bound, const Eigen::VectorXd& x,
                                   const std::vector<bool>& movable = {});

}  // namespace inertial
