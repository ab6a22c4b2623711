/// @file body_representation.hpp
/// One rigid body written as numbers in one of five representations, and converted from any of
/// them to any other (`inertial convert`): pi [m hx hy hz Ixx Iyy Izz Ixy Iyz Ixz] about the frame
/// origin; theta, the log-Cholesky parameters (eq. 8, relative to a reference body, eq. 11); mci
/// [m cx cy cz Ixx Iyy Izz Ixy Iyz Ixz] with the inertia about the center of mass; pseudo, the 4x4
/// pseudo-inertia J row by row; spatial, the 6x6 spatial inertia (eq. 2) row by row.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "inertial/inertia/consistency.hpp"
#include "inertial/inertia/inertial_params.hpp"

namespace inertial {

/// Every representation by name ("mci", "pi", "pseudo", "spatial", "theta") with how many numbers
/// it takes (10, 16 for pseudo, 36 for spatial).
const std::map<std::string, int>& BodyRepresentationSizes();

struct BodyConversionRequest {
  std::string from, to;        ///< representation names (BodyRepresentationSizes)
  std::vector<double> values;  ///< the body in `from`: exactly as many numbers as it takes
  /// The log-Cholesky reference body (eq. 11), fully physically consistent; none: the identity
  /// reference (1 kg at the origin, unit second moments).
  std::optional<InertialParams> reference;
  /// Convert a body that is not fully physically consistent where the target exists (never to theta).
  bool allow_inconsistent = false;
};

struct BodyConversion {
  std::string to;             ///< the representation of `value`
  Eigen::MatrixXd value;      ///< a column of 10 for pi, theta and mci; the 4x4 or 6x6 matrix otherwise
  ConsistencyReport consistency;  ///< the numerical check of the body
  /// The body is fully consistent: by the check, or by construction (every finite theta is, even
  /// one so thin that its margins fall below the check's tolerance, Section IV-B).
  bool consistent = false;
};

/// Converts `request.values` from one representation to another.
/// @throws std::invalid_argument (the message says why) when the count of values is not the size of
/// `from` ("pi takes 10 numbers, got 9"), when the numbers are no body of `from`
/// (an mci of zero mass, a pseudo or spatial matrix not of its form, a theta that overflows double
/// precision), when the body is not fully consistent (unless allow_inconsistent, and never for theta
/// output), or when it has no `to` (mci of a massless body; theta without a Cholesky factor).
/// @throws std::out_of_range for an unknown representation name.
BodyConversion ConvertBody(const BodyConversionRequest& request);

}  // namespace inertial
