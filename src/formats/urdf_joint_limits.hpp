/// @file urdf_joint_limits.hpp
/// (Private to the formats layer.) The moving joints' `<limit lower upper velocity effort>` of a
/// URDF document, read strictly (format in urdf_model.hpp).
#pragma once

#include <tinyxml2.h>

#include <string>
#include <vector>

#include "inertial/model/joint_limits.hpp"

namespace inertial::detail {

/// One JointLimits per name of `moving_joints` (robot: the document's <robot> element). A joint's
/// `continuous` type ignores lower and upper (as the URDF specification says).
/// @throws UrdfError naming source, joint and attribute for a number that is not a finite decimal,
/// lower > upper, or a negative velocity or effort.
std::vector<JointLimits> ReadJointLimits(const tinyxml2::XMLElement& robot, const std::string& source,
                                         const std::vector<std::string>& moving_joints);

}  // namespace inertial::detail
