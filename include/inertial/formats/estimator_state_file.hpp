/// @file estimator_state_file.hpp
/// An online estimator's state (recursive_estimator.hpp's EstimatorState: kind, x, covariance,
/// time, counters) as a small JSON document, so that a restarted process continues where it
/// stopped. Numbers are written with round-trip precision: a saved and loaded state is the same
/// to the last bit. Files are written atomically (a temporary file renamed over the target), so a
/// crash mid-write never leaves a truncated checkpoint.
///
/// Layout: {"format": "inertial-estimator-state", "version": 1, "kind": "...", "model": "...",
/// "x": [...], "P": [[...], ...] (or []), "has_time": bool, "last_time": s,
/// "counters": {"accepted": N, "non_finite": N, ...}}. "model" is a free description the writer
/// chooses (e.g. the URDF path and effects) and the reader may compare.
#pragma once

#include <stdexcept>
#include <string>

#include "inertial/estimation/online/recursive_estimator.hpp"

namespace inertial {

struct StateFileError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

std::string EstimatorStateToJson(const EstimatorState& state, const std::string& model_description);
/// @throws StateFileError naming `source` and what is wrong (not JSON, wrong format or version,
/// missing or mistyped fields, a covariance that is not square of the parameters' size).
EstimatorState EstimatorStateFromJson(const std::string& text, const std::string& source,
                                      std::string* model_description = nullptr);

/// @throws StateFileError if the file cannot be written (naming it and the system's reason).
void SaveEstimatorState(const std::string& path, const EstimatorState& state, const std::string& model_description);
/// @throws StateFileError if the file cannot be read or is malformed.
EstimatorState LoadEstimatorState(const std::string& path, std::string* model_description = nullptr);

}  // namespace inertial
