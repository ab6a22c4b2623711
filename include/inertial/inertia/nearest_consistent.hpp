/// @file nearest_consistent.hpp
/// Repair of an impossible inertia (published URDFs often contain them): the nearest fully
/// physically consistent body with the same mass and centre of mass.
///
/// "Nearest" is in the Frobenius norm of the pseudo-inertia taken at the COM, J_c = [[Sigma_c, 0],
/// [0, m]] with Sigma_c the second moments of mass about the COM (Sigma_c = tr(I_c)/2 1 - I_c).
/// With m and c fixed, the nearest J_c whose Sigma_c has eigenvalues >= eps is obtained by clipping
/// Sigma_c's eigenvalues from below at eps (keeping its eigenvectors, the principal axes). Positive
/// Sigma_c eigenvalues are exactly the strict triangle inequalities on the principal moments, so the
/// result is fully consistent. eps = max(1e-3 max_i sigma_i, m (1 mm)^2): the body is never thinner
/// than a millimetre of spread.
#pragma once

#include <string>

#include "inertial/inertia/inertial_params.hpp"

namespace inertial {

/// Returns false (and *why says so, *repaired untouched) if the body cannot be repaired this way:
/// mass not positive, or a number not finite. A consistent body is returned unchanged.
bool NearestConsistentBody(const InertialParams& body, InertialParams* repaired, std::string* why = nullptr);

}  // namespace inertial
