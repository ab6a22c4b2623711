/// @file body_conversion_report.hpp
/// What `inertial convert` prints of a converted body (body_representation.hpp): the numbers as
/// text or JSON, and the note or warning about a body the consistency check could not confirm.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "inertial/formats/body_representation.hpp"

namespace inertial {

/// "<to>: n n n ...\n" with 17 significant digits (round trip) and -0 printed as 0; a matrix one
/// row per line, the rows after the first indented under the first number.
std::string BodyConversionText(const BodyConversion& conversion);

/// {"<to>": [numbers] or [[row], ...], "consistency": {fully_consistent, margins_above_tolerance,
/// mass, min_inertia_eigenvalue_com, min_triangle_margin, min_pseudo_inertia_eigenvalue, reason}};
/// fully_consistent is BodyConversion::consistent, margins_above_tolerance the numerical check.
nlohmann::json BodyConversionJson(const BodyConversion& conversion);

/// Empty for a body the check confirms; else one line: "note: consistent by construction ..." for
/// a body consistent by construction, "warning: <reason>" for an inconsistent one (allowed).
std::string BodyConversionNote(const BodyConversion& conversion);

}  // namespace inertial
