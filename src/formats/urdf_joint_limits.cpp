#include "urdf_joint_limits.hpp"

#include <cstring>
#include <map>

#include "inertial/formats/number_parsing.hpp"
#include "inertial/formats/urdf_model.hpp"
#include "inertial/model/number_text.hpp"
#include "urdf_effects.hpp"

namespace inertial::detail {
namespace {

// The attribute's value, or `absent` when the element does not have it.
double LimitAttribute(const tinyxml2::XMLElement& limit, const char* name, const std::string& where, double absent) {
  const char* text = limit.Attribute(name);
  if (text == nullptr) return absent;
  try {
    return ParseDouble(text, std::string(name));
  } catch (const InvalidNumber& e) {
    throw UrdfError(where + ": <limit> (line " + std::to_string(limit.GetLineNum()) + "): attribute " + e.what());
  }
}

}  // namespace

std::vector<JointLimits> ReadJointLimits(const tinyxml2::XMLElement& robot, const std::string& source,
                                         const std::vector<std::string>& moving_joints) {
  std::map<std::string, const tinyxml2::XMLElement*> element_of;
  for (const tinyxml2::XMLElement* j = robot.FirstChildElement("joint"); j; j = j->NextSiblingElement("joint")) {
    if (const char* name = j->Attribute("name")) element_of.emplace(name, j);  // the first, as urdfdom
  }
  std::vector<JointLimits> limits(moving_joints.size());
  for (std::size_t k = 0; k < moving_joints.size(); ++k) {
    const auto it = element_of.find(moving_joints[k]);
    const tinyxml2::XMLElement* limit = it == element_of.end() ? nullptr : it->second->FirstChildElement("limit");
    if (limit == nullptr) continue;
    const std::string where = source + ": joint '" + moving_joints[k] + "'";
    JointLimits& l = limits[k];
    const char* type = it->second->Attribute("type");
    if (type == nullptr || std::strcmp(type, "continuous") != 0) {
      l.lower = LimitAttribute(*limit, "lower", where, l.lower);
      l.upper = LimitAttribute(*limit, "upper", where, l.upper);
      if (l.lower > l.upper) {
        throw UrdfError(where + ": <limit> lower " + FormatNumber(l.lower, kRoundTripDigits) + " is above upper " + FormatNumber(l.upper, kRoundTripDigits));
      }
    }
    l.velocity = LimitAttribute(*limit, "velocity", where, 0.0);
    l.effort = LimitAttribute(*limit, "effort", where, 0.0);
    if (l.velocity < 0 || l.effort < 0) {
      throw UrdfError(where + ": <limit> velocity and effort must be >= 0 (got " + FormatNumber(l.velocity, kRoundTripDigits) + ", " +
                      FormatNumber(l.effort, kRoundTripDigits) + ")");
    }
    // 0 (or absent) states no limit: exporters write 0 for "unknown", and a moving joint that can
    // neither move nor push is not what the file means.
    if (l.velocity == 0) l.velocity = JointLimits{}.velocity;
    if (l.effort == 0) l.effort = JointLimits{}.effort;
  }
  return limits;
}

}  // namespace inertial::detail
