/// @file rejection.hpp
/// The one vocabulary of the sample pipeline (source -> decode -> preprocess -> estimator ->
/// sinks): why an input gave no update, whichever stage refused it, and one counters type that
/// every stage keeps. Fixed-size (an array indexed by the reason), so counting never allocates.
///
/// Stages and the reasons they give:
/// - decoding a message or frame: kDecode, kWrongSize, kUnknownJoint, kNonFinite; a candump line
///   that is not a frame: kBadLine; CAN frames: kUnknownId, kMalformed, kErrorFrame, kLate,
///   kSuperseded;
/// - preprocessing (stream_preprocessor.hpp): kPriming, kOutOfOrder, kNonFinite;
/// - the estimator (UpdateStatus, update_status.hpp): kNonFinite, kOutOfOrder, kWrongSize,
///   kOutlier, kNumerical;
/// - the daemon's queue: kQueueFull.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "inertial/signal/update_status.hpp"

namespace inertial {

enum class Rejection : std::uint8_t {
  kNone = 0,      ///< not rejected
  kDecode,        ///< the bytes are not a message of the expected type
  kWrongSize,     ///< arrays or dimensions that do not match the model
  kUnknownJoint,  ///< a joint name the model does not have
  kNonFinite,     ///< a NaN or Inf (time, a value, or a derived acceleration)
  kOutOfOrder,    ///< time not after the previous sample's
  kPriming,       ///< the first sample of a stream only primes a derivative filter
  kUnknownId,     ///< a CAN identifier no configured motor of the model answers with
  kMalformed,     ///< a motor's frame that does not decode
  kErrorFrame,    ///< a CAN error frame
  kLate,          ///< a motor reading older than the tick window, or a tick not after the previous
  kSuperseded,    ///< a motor reading replaced by a newer one before its tick completed
  kBadLine,       ///< a candump line that does not parse
  kOutlier,       ///< innovation beyond the estimator's gate
  kNumerical,     ///< the update would have left the estimate non-finite or out of range
  kQueueFull,     ///< dropped: the estimator's queue was full
};
inline constexpr int kNumRejections = 16;

/// "ok", "decode", "wrong_size", "unknown_joint", "non_finite", "out_of_order", "priming",
/// "unknown_id", "malformed", "error_frame", "late", "superseded", "bad_line", "outlier",
/// "numerical", "queue_full": the names counters are published and printed under.
std::string_view ToString(Rejection r);

/// The reason of an estimator's status; kNone for kAccepted and kBuffered.
Rejection RejectionOf(UpdateStatus status);

/// The reason named `name` (as ToString), or nullopt.
std::optional<Rejection> RejectionNamed(std::string_view name);

/// What one stage (or the whole pipeline) did with its inputs. Every input is received, then
/// either passed on (accepted: by the estimator, a sample updated it; by a decoder, it gave a
/// sample), buffered, or rejected for one reason.
struct SampleCounters {
  std::uint64_t received = 0;
  std::uint64_t accepted = 0;
  std::uint64_t buffered = 0;  ///< kept for later (the first twist of a body's pair)
  std::array<std::uint64_t, kNumRejections> rejected{};

  void Reject(Rejection r, std::uint64_t n = 1) { rejected[static_cast<int>(r)] += n; }
  std::uint64_t operator[](Rejection r) const { return rejected[static_cast<int>(r)]; }
  /// Every rejection (kNone's slot is never counted).
  std::uint64_t total_rejected() const;
  /// The estimator's outcome of one sample: accepted, buffered or rejected.
  void Count(UpdateStatus status);
};

/// The rejections by reason, in the enum's order, those counted only: "decode 3, late 2" (empty
/// if none). `except` (e.g. kQueueFull, reported apart) is left out.
std::string RejectionsText(const SampleCounters& counters, Rejection except = Rejection::kNone);

}  // namespace inertial
