#include "inertial/diagnosis/explained_error.hpp"

#include <stdexcept>

namespace inertial {

double ExplainedShare(const Eigen::VectorXd& rms_without, const Eigen::VectorXd& rms_with) {
  if (rms_without.size() == 0 || rms_without.size() != rms_with.size()) {
    throw std::invalid_argument("explained share: the error vectors must have the same non-zero size");
  }
  double sum = 0.0;
  for (int c = 0; c < rms_without.size(); ++c) {
    const double before = rms_without[c] * rms_without[c];
    if (before > 0.0) sum += 1.0 - rms_with[c] * rms_with[c] / before;
  }
  return sum / static_cast<double>(rms_without.size());
}

bool SupportedByHeldOutData(const TorqueErrors& without, const TorqueErrors& with, double explained,
                            double min_explained, double min_gain) {
  if (!(explained >= min_explained) || !(with.total_rms < without.total_rms)) return false;
  for (int c = 0; c < without.relative_rms.size(); ++c) {
    if (without.relative_rms[c] - with.relative_rms[c] >= min_gain) return true;
  }
  return false;
}

}  // namespace inertial
