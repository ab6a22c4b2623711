#include "inertial/report/fit_failure_text.hpp"

#include <cmath>

namespace inertial {

std::string FitFailureText(const std::string& data, const IdentificationRun& run, const JointSamples& train,
                           bool outlier_rejection) {
  std::string text = "Error: " + data + ": the fit failed numerically (stopped on " + std::string(ToString(run.fit.lm.reason)) +
                     (std::isfinite(run.fit.data_cost) ? "" : ", non-finite cost") + ")";
  const std::vector<std::string> extremes = DescribeExtremeValues(train);
  if (extremes.empty()) return text + "; no value of the data stands out: check units (--time-scale) and the model\n";
  text += ": the data hold values no sensor reading can have:\n";
  for (const std::string& e : extremes) text += "  " + e + "\n";
  return text + (outlier_rejection ? "hint: fix or remove these rows (--skip-bad-rows skips malformed ones)\n"
                                   : "hint: without --no-outlier-rejection such rows are left out\n");
}

}  // namespace inertial
