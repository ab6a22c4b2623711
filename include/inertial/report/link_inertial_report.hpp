/// @file link_inertial_report.hpp
/// What `inertial check` prints of a URDF's link inertials (link_inertial_check.hpp): one entry per
/// link with its margins, the reason and the repair of each impossible one, the totals, and the
/// repaired copy if one was written; as text or JSON.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "inertial/formats/link_inertial_check.hpp"

namespace inertial {

/// "<path>: robot '<name>', N links, M moving joints", one entry per link (margins with 4
/// significant digits), "N inertials checked: ...", and "wrote <copy>: ..." when `repair` is given.
std::string LinkInertialText(const UrdfInertialCheck& check, const UrdfRepair* repair = nullptr);

/// {model, links[{link, used_by_dynamics, inertial ("absent", "zero", "present"),
/// physically_consistent (null without a body), mass, min_inertia_eigenvalue_com,
/// min_triangle_margin, min_pseudo_inertia_eigenvalue, reason, repaired_inertia_about_com [Ixx Iyy
/// Izz Ixy Iyz Ixz] or repair (why not)}], checked, impossible, all_consistent, repaired (with a repair)}.
nlohmann::json LinkInertialJson(const UrdfInertialCheck& check, const UrdfRepair* repair = nullptr);

}  // namespace inertial
