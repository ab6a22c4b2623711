/// @file region_plausibility.hpp
/// Whether an estimated body is one its link could have, judged against its region (body_region.hpp)
/// and its URDF prior, in numbers and in words, for every command that prints or writes bodies.
///
/// The verdicts, each reasoned, none fitted to a robot:
///  - outside its region (slack s < 0): its mass lies where the link is not. A fit cannot return
///    such a body (region_barrier.hpp); a model file or a URDF can.
///  - denser than steel over its whole region (mass > max_mass): impossible for a link (body_region.hpp).
///  - mass more than kImplausibleMassRatio times its URDF's, or less than its inverse: a CAD mass is
///    off by tens of per cent (plausibility.hpp), a link three times heavier or lighter than drawn is
///    a different link, a payload or a fit explaining something else (friction, a spring, a
///    sensor offset) with mass.
///  - on its region's edge (s < kRegionEdgeSlack) after a fit: the data pushed the body against its
///    region, so the region, not the data, decided where its mass is. A solid uniform ellipsoid
///    filling the region has s = 0.4 and a thin shell on its surface s = 0; below 0.05 the mass's
///    mean normalized squared distance from the region's centre exceeds 0.95, i.e. nearly all of it
///    sits on the region's surface, which no link's mass does. It is plausible in itself but says
///    the model lacks something the fit tried to explain with this body.
/// Density: mass over the region's volume, for the reader (a robot's links average 1,000 to 3,000
/// kg/m^3 over their bounding volumes).
///
/// Conventions: SI units; body, prior and region in one frame (the tree body's).
#pragma once

#include <string>

#include <optional>

#include "inertial/model/body_region.hpp"
#include "inertial/model/robot_dynamics.hpp"

namespace inertial {

inline constexpr double kImplausibleMassRatio = 3.0;
inline constexpr double kRegionEdgeSlack = 0.05;

struct RegionPlausibility {
  double slack = 1.0;       ///< tr(Q J) / m, in (-inf, 1]
  double density = 0.0;     ///< mass / region volume [kg/m^3]
  double mass_ratio = 1.0;  ///< mass / the prior's
  bool inside = true;       ///< slack >= 0 and mass <= max_mass
  bool on_edge = false;     ///< inside, slack < kRegionEdgeSlack
  bool plausible = true;    ///< inside, and the mass ratio within kImplausibleMassRatio
  bool mass_compared = true;  ///< the mass was judged against the prior's (JudgeAgainstRegion's drawn_prior)
  /// Empty when plausible and not on the edge; otherwise what is wrong, in a sentence without the
  /// body's name (the caller prefixes it).
  std::string words;
};

/// `drawn_prior`: the prior is a drawing of this body (a URDF link), so its mass is a reference;
/// false for a payload, whose prior is a guess (its mass is then not compared).
/// @throws std::invalid_argument if the prior's mass is not positive.
RegionPlausibility JudgeAgainstRegion(const InertialParams& body, const InertialParams& prior, const BodyRegion& region,
                                      bool drawn_prior = true);

/// Whether `body`'s prior is a drawing of it (a URDF link), whose mass is a reference: every body with
/// a region but a payload (region from its reach), whose prior is a guess.
bool HasDrawnPrior(const EstimatedBody& body);

/// An estimated body at its theta (x's 10 entries), or nullopt if it has no region (a rotor).
std::optional<RegionPlausibility> JudgeEstimatedBody(const EstimatedBody& body, const Vector10& theta);
/// The same for the body as reported (RobotDynamics::BodyInertia: in its report frame).
std::optional<RegionPlausibility> JudgeReportedBody(const EstimatedBody& body, const InertialParams& in_report_frame);

}  // namespace inertial
