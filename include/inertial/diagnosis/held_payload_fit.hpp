/// @file held_payload_fit.hpp
/// Whether a link the online fit bends away from its URDF is a link carrying a payload: the payload
/// a plausible object held by that link would have to be, fitted to the link's estimate under the
/// estimate's own uncertainty, and what is left of the departure once it is taken out.
///
/// The link's estimate e (pi, in its frame) with covariance Sigma, its URDF body p. Holding the
/// link at p and adding a payload body phi changes the fit's cost, to second order (the Laplace
/// approximation of the fit about its optimum, the other parameters re-optimized: Sigma is the
/// marginal covariance of the link's pi), by
///
///   0.5 chi2(phi),   chi2(phi) = (e - p - phi)^T Sigma^+ (e - p - phi),
///
/// Sigma^+ the pseudo-inverse over Sigma's range (eigenvalues below 1e-12 of the largest dropped:
/// directions the estimate does not vary in are not judged). The payload is the minimizer of chi2
/// over point masses m > 0 (x = (log m, c): unconstrained in m) whose COM c lies in the payload's
/// region (body_region.hpp: RobotDynamics's region of a payload on that link, about the link's
/// frame origin, of the robot's longest segment), kept there by a one-sided log barrier on the
/// region's slack 1 - (c - c0)^T P (c - c0) (region_barrier.hpp's OneSidedLogBarrier) with weight
/// kHeldPayloadBarrierWeight chi2(0). Sigma's eigenvalues are cut in the body's own units (m0,
/// m0 reach, m0 reach^2), so that the cut compares like with like. A point mass, not a body of ten parameters: its four
/// are fixed by the mass and first moment the data determine well, where a full body would take
/// whatever the estimate's loosely determined second moments leave (those the prior holds) and
/// make the rest of the link no body. A payload's own inertia about its COM stays with the link.
/// The batch diagnosis tests the same hypothesis by refitting the whole model with the link held
/// and a payload body in its region (joint_diagnosis.hpp); online the statistics' curvature stands
/// in for the refit.
///
/// What decides (online_diagnosis.cpp): the payload not pinned at its region's boundary (slack at
/// least kBarrierOnset: one the data push outward is a payload the link cannot hold); the link
/// with the payload taken out, e - phi, a body within the estimate's uncertainty (made the nearest
/// consistent one, nearest_consistent.hpp, by a change of chi2 at most 4: two standard deviations);
/// and that body against its URDF with the same margins and tolerance as the bent link
/// (plausibility.hpp). A departure no plausible payload carries (a link whose CAD is wrong, a
/// payload that would have to sit beyond the robot's reach) fails one of them, and is no payload.
///
/// Conventions: SI units; pi = [m, h, I about the frame origin] (inertial_params.hpp), in the
/// link's report frame.
#pragma once

#include <optional>

#include "inertial/inertia/inertial_params.hpp"

namespace inertial {

/// The barrier's weight as a share of chi2(0), the departure the payload is to carry (scale-free,
/// as the fit's own barrier, region_barrier.hpp): negligible while the payload is well inside
/// (the barrier is zero above kBarrierOnset), while one the estimate pushes against the region's
/// boundary stops at a small positive slack instead of creeping along it.
inline constexpr double kHeldPayloadBarrierWeight = 1e-3;

/// pi of a point mass m at c, and d pi / d c into d_dc when not null.
Vector10 PointMassPi(double m, const Vector3& c, Eigen::Matrix<double, 10, 3>* d_dc = nullptr);

struct HeldPayloadFit {
  InertialParams payload;       ///< phi: a point mass inside its region
  double chi2_held = 0.0;       ///< chi2(0): the link held at its URDF with nothing added
  double chi2 = 0.0;            ///< chi2(phi)
  int rank = 0;                 ///< of Sigma: the directions judged
  double slack = 0.0;           ///< phi's region slack (1 at the region's centre, 0 on its boundary)
  double region_radius = 0.0;   ///< [m] the payload region's largest semi-axis
  bool converged = false;
  Matrix10 information = Matrix10::Zero();  ///< Sigma^+ (chi2 of a pi difference v: v^T information v)
};

/// The payload on a link whose frame origin is the centre of its region, a ball of radius `reach`
/// (> 0; RobotDynamics's payload region of that radius). nullopt if nothing can be fitted: e - p not heavier than nothing, Sigma
/// zero or not finite, or a number not finite.
std::optional<HeldPayloadFit> FitHeldPayload(const InertialParams& estimate, const InertialParams& prior,
                                             const Matrix10& covariance, double reach);

}  // namespace inertial
