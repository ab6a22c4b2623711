/// @file update_status.hpp
/// What became of one sample given to an online estimator, and the counters of every outcome.
/// Estimators never throw on the update path: a sample they cannot use is rejected with a status,
/// counted, and the estimate is left exactly as it was.
#pragma once

#include <array>
#include <cstdint>
#include <string_view>

namespace inertial {

enum class UpdateStatus : int {
  kAccepted = 0,
  kNonFinite,     ///< a NaN or Inf in the sample (time, regressor or measurement)
  kOutOfOrder,    ///< time not strictly after the last accepted sample's
  kWrongSize,     ///< the sample's dimensions do not match the model
  kOutlier,       ///< innovation beyond the gate (Mahalanobis distance)
  kNumerical,     ///< the update would have left the estimate non-finite or out of range
  kBuffered,      ///< kept for later, no update yet (the first twist of a pair)
};
inline constexpr int kNumUpdateStatuses = 7;

/// True for the statuses that reject a sample (not kAccepted, not kBuffered).
inline bool IsRejection(UpdateStatus s) { return s != UpdateStatus::kAccepted && s != UpdateStatus::kBuffered; }

/// "accepted", "non_finite", "out_of_order", "wrong_size", "outlier", "numerical", "buffered".
std::string_view ToString(UpdateStatus status);

/// Counts per status (index = static_cast<int>(status)).
struct UpdateCounters {
  std::array<std::uint64_t, kNumUpdateStatuses> count{};
  void Add(UpdateStatus s) { ++count[static_cast<int>(s)]; }
  std::uint64_t accepted() const { return count[0]; }
  std::uint64_t rejected() const {
    std::uint64_t r = 0;
    for (int k = 0; k < kNumUpdateStatuses; ++k) r += IsRejection(static_cast<UpdateStatus>(k)) ? count[k] : 0;
    return r;
  }
  std::uint64_t operator[](UpdateStatus s) const { return count[static_cast<int>(s)]; }
};

}  // namespace inertial
