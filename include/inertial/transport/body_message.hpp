/// @file body_message.hpp
/// inertial.body_wrench_t messages (lcmtypes/body_wrench_t.lcm) into single-body samples, decoded
/// by lcm_layout.hpp (nothing trusted), and back.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "inertial/model/body_sample.hpp"
#include "inertial/transport/joint_message.hpp"

namespace inertial {

/// The layout of inertial.body_wrench_t.
const LcmLayout& BodyWrenchLayout();

/// Decodes one message into *sample; kWrongSize if it has no twist (the velocity product needs it),
/// kNonFinite for a NaN or Inf. *why (optional) says what is wrong.
Rejection DecodeBodyWrench(const void* data, std::size_t size, BodySample* sample, std::string* why = nullptr);

/// Encodes a sample (utime = t * 1e6; has_twist true).
std::vector<std::uint8_t> EncodeBodyWrench(const BodySample& sample, const std::string& frame);

}  // namespace inertial
