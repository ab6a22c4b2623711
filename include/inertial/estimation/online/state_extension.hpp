/// @file state_extension.hpp
/// An estimator state carried into a model with more parameters, entry by entry by name: what
/// lets inertiald restart from its checkpoint with more effects (`--effects` grown by
/// coulomb@knee, a payload, a rotor) without losing what it has learnt.
///
/// The result is the new estimator's own fresh state (x at its priors, P its initial covariance:
/// the new parameters start at their priors with their prior variance), with every saved entry
/// copied in by name: x_i, and the covariance block among the saved entries (their
/// cross-covariances included); the covariances between a new entry and a saved one are zero (the
/// new parameter's prior is independent of what the data said of the others); time and counters
/// come from the saved state. The covariance stays symmetric positive definite when both inputs
/// are (a symmetric permutation of the block diagonal of two such blocks). Pure: no I/O.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "inertial/estimation/online/recursive_estimator.hpp"

namespace inertial {

/// ExtendEstimatorState's result.
struct ExtendedState {
  EstimatorState state;             ///< fresh's, with saved's entries copied in by name
  std::vector<std::string> added;   ///< fresh's names not in saved, in fresh's order (left at the priors)
};

/// `saved` (entries named `saved_names`, in x's order) carried into `fresh`, the initial state of
/// an estimator of the larger model (entries named `fresh_names`).
/// Returns nullopt and sets *why (if given) when it cannot be done, naming what differs: another
/// estimator kind; a name list that does not have one name per entry of x, or a name given twice;
/// a covariance in one state and not in the other, or not square of x's size; a saved entry whose
/// name is not among fresh_names (all such names are listed: e.g. an effect removed).
std::optional<ExtendedState> ExtendEstimatorState(const EstimatorState& saved, const std::vector<std::string>& saved_names,
                                                  const EstimatorState& fresh, const std::vector<std::string>& fresh_names,
                                                  std::string* why);

}  // namespace inertial
