#include "inertial/signal/update_status.hpp"

namespace inertial {

std::string_view ToString(UpdateStatus status) {
  switch (status) {
    case UpdateStatus::kAccepted: return "accepted";
    case UpdateStatus::kNonFinite: return "non_finite";
    case UpdateStatus::kOutOfOrder: return "out_of_order";
    case UpdateStatus::kWrongSize: return "wrong_size";
    case UpdateStatus::kOutlier: return "outlier";
    case UpdateStatus::kNumerical: return "numerical";
    case UpdateStatus::kBuffered: return "buffered";
  }
  return "unknown";
}

}  // namespace inertial
