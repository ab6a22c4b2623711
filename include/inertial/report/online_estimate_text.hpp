/// @file online_estimate_text.hpp
/// The online estimator's current estimate as text, one line per body of its model: mass and COM,
/// with the standard deviations of the estimator's covariance where it keeps one
/// (uncertainty_report.hpp). What `inertial replay` prints as its final estimate.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "inertial/estimation/online/online_joint_estimator.hpp"

namespace inertial {

/// "final estimate:\n" then "  <body>: mass <m> kg, COM [<x> <y> <z>] m\n" per body; for an
/// estimator with a covariance "final estimate (+- one standard deviation <source>):\n" then
/// "  <body>: <BodyUncertaintyText>\n". Numbers as an ostream prints them (6 significant digits).
std::string OnlineEstimateText(const OnlineJointEstimator& estimator);

/// The same estimate as JSON (`replay --json`'s "final", the Python module's estimate()): the
/// estimator's name; the bodies (mass, COM, inertia; with standard deviations and "held by the prior"
/// where the estimator has them) and the effect coefficients, as identify's JSON gives them; with the
/// online fit, its per-joint noise and its number of solves.
nlohmann::json OnlineEstimateJson(const OnlineJointEstimator& estimator);

}  // namespace inertial
