/// @file diagnosis_message.hpp
/// The online diagnosis as inertiald publishes it: inertial.diagnosis_t (lcmtypes/diagnosis_t.lcm),
/// the suggestions ranked best first with their one-line explanations; and payload events,
/// inertial.payload_event_t.
#pragma once

#include <cstdint>
#include <vector>

#include "inertial/diagnosis/online_diagnosis.hpp"
#include "inertial/diagnosis/payload_event.hpp"

namespace inertial {

/// The encoded message of `result` at time utime [microseconds].
std::vector<std::uint8_t> EncodeDiagnosis(const OnlineDiagnosisResult& result, std::int64_t utime);

/// A payload picked up or put down (payload_event.hpp) as inertial.payload_event_t.
std::vector<std::uint8_t> EncodePayloadEvent(const PayloadEvent& event);

}  // namespace inertial
