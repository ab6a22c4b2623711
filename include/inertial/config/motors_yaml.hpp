/// @file motors_yaml.hpp
/// motors.yaml (the format is in transport/motor_codec.hpp's file comment) into a CanConfig, with
/// yaml-cpp: every key checked, nothing assumed.
#pragma once

#include <string>

#include "inertial/transport/motor_codec.hpp"

namespace inertial {

/// Reads motors.yaml (see the file comment). @throws std::invalid_argument naming the file, the
/// motor and the key (unknown keys, bad ranges, two motors on one frame or one joint, values of
/// the wrong kind, a file over kMaxSettingsFileBytes: input_file.hpp); std::runtime_error if the
/// file cannot be read.
CanConfig LoadCanConfig(const std::string& path);
CanConfig ParseCanConfig(const std::string& yaml_text, const std::string& source);

}  // namespace inertial
