/// @file departure_margins.hpp
/// How far an estimated body may stray from its prior by its own uncertainty before the departure
/// counts (plausibility.hpp's DepartureMargins), from the estimate's covariance: the batch fit's
/// (fit_uncertainty.hpp, joint_diagnosis.hpp) and the online estimator's (online_diagnosis.hpp)
/// alike. Conventions: pi = [m, hx, hy, hz, Ixx, Iyy, Izz, Ixy, Iyz, Ixz] about the body frame's
/// origin, SI units.
#pragma once

#include "inertial/estimation/parameter_layout.hpp"
#include "inertial/inertia/plausibility.hpp"

namespace inertial {

/// Departures count beyond kDepartureMargin standard deviations of the estimate (plausibility.hpp):
/// a link's poorly excited directions stray by their uncertainty, not by a missing effect. Two: a
/// true link inside the tolerance (a CAD model's ordinary error, factors up to about 1.4 against a
/// tolerance of 1.75) must be pushed by noise past the tolerance and 2 standard deviations more to
/// count, rare even among the tens of quantities of a robot's links (one-sided 2.3 % for a link at
/// the tolerance itself, far less inside it); three would hide a payload as heavy as an arm's last
/// link, whose mass the data fix to about a quarter of it.
inline constexpr double kDepartureMargin = 2.0;

/// The margins of a body whose prior is `prior`, whose estimate has standard deviations `std` and
/// pi covariance `pi_covariance` (same frame): kDepartureMargin standard deviations of the mass and
/// of the inertia about the COM, and the first moment about the prior's COM, m c - m c0 = h - m c0
/// (linear in pi), with kDepartureMargin^2 times its covariance. A mass or COM that is not finite
/// (undetermined) gives an infinite first-moment margin: no departure of it is counted.
DepartureMargins DepartureMarginsOf(const InertialParams& prior, const BodyUncertainty& std,
                                    const Matrix10& pi_covariance);

}  // namespace inertial
