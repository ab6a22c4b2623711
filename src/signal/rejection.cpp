#include "inertial/signal/rejection.hpp"

namespace inertial {

std::string_view ToString(Rejection r) {
  switch (r) {
    case Rejection::kNone: return "ok";
    case Rejection::kDecode: return "decode";
    case Rejection::kWrongSize: return "wrong_size";
    case Rejection::kUnknownJoint: return "unknown_joint";
    case Rejection::kNonFinite: return "non_finite";
    case Rejection::kOutOfOrder: return "out_of_order";
    case Rejection::kPriming: return "priming";
    case Rejection::kUnknownId: return "unknown_id";
    case Rejection::kMalformed: return "malformed";
    case Rejection::kErrorFrame: return "error_frame";
    case Rejection::kLate: return "late";
    case Rejection::kSuperseded: return "superseded";
    case Rejection::kBadLine: return "bad_line";
    case Rejection::kOutlier: return "outlier";
    case Rejection::kNumerical: return "numerical";
    case Rejection::kQueueFull: return "queue_full";
  }
  return "unknown";
}

Rejection RejectionOf(UpdateStatus status) {
  switch (status) {
    case UpdateStatus::kAccepted:
    case UpdateStatus::kBuffered: return Rejection::kNone;
    case UpdateStatus::kNonFinite: return Rejection::kNonFinite;
    case UpdateStatus::kOutOfOrder: return Rejection::kOutOfOrder;
    case UpdateStatus::kWrongSize: return Rejection::kWrongSize;
    case UpdateStatus::kOutlier: return Rejection::kOutlier;
    case UpdateStatus::kNumerical: return Rejection::kNumerical;
  }
  return Rejection::kNumerical;
}

std::optional<Rejection> RejectionNamed(std::string_view name) {
  for (int k = 0; k < kNumRejections; ++k) {
    if (ToString(static_cast<Rejection>(k)) == name) return static_cast<Rejection>(k);
  }
  return std::nullopt;
}

std::uint64_t SampleCounters::total_rejected() const {
  std::uint64_t n = 0;
  for (int k = 1; k < kNumRejections; ++k) n += rejected[static_cast<std::size_t>(k)];
  return n;
}

void SampleCounters::Count(UpdateStatus status) {
  if (status == UpdateStatus::kAccepted) {
    ++accepted;
  } else if (status == UpdateStatus::kBuffered) {
    ++buffered;
  } else {
    Reject(RejectionOf(status));
  }
}

std::string RejectionsText(const SampleCounters& counters, Rejection except) {
  std::string text;
  for (int k = 1; k < kNumRejections; ++k) {
    const Rejection r = static_cast<Rejection>(k);
    if (r == except || counters[r] == 0) continue;
    text += (text.empty() ? "" : ", ") + std::string(ToString(r)) + " " + std::to_string(counters[r]);
  }
  return text;
}

}  // namespace inertial
