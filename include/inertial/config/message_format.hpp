/// @file message_format.hpp
/// The JSON descriptions of LCM messages (a user's own message types, so that nobody need change a
/// controller): an LCM layout (transport/lcm_layout.hpp) and a joint-state format
/// (transport/joint_message.hpp), read with nlohmann-json; every key checked.
#pragma once

#include <nlohmann/json.hpp>

#include "inertial/transport/joint_message.hpp"
#include "inertial/transport/lcm_layout.hpp"

namespace inertial {

/// A layout from JSON: {"type": "name", "fields": [{"name": "q", "type": "float", "length": 12},
/// {"name": "n", "type": "int32_t"}, {"name": "tau", "type": "double", "length": "n"}, ...]}.
/// @throws std::invalid_argument naming the entry and what is wrong.
LcmLayout ParseLcmLayout(const nlohmann::json& j);

/// From JSON: {"layout": {...lcm_layout...}, "utime": "field" | null, "names": "field" |
/// "joint_names": [...], "q": ..., "qd": ..., "qdd": "field" | null, "tau": ..., "accel_cutoff_hz": 20}.
/// Missing keys keep the defaults of inertial.joint_state_t. @throws std::invalid_argument.
JointMessageFormat ParseJointMessageFormat(const nlohmann::json& j);

}  // namespace inertial
