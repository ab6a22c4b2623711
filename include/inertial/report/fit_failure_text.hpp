/// @file fit_failure_text.hpp
/// The error `inertial identify` prints when the fit fails numerically (IdentificationRun::failed):
/// where it stopped, and the values of the training data no sensor reading can have with what to do
/// about them, or, if none stands out, what else to check.
#pragma once

#include <string>

#include "inertial/report/identification_report.hpp"

namespace inertial {

/// "Error: <data>: the fit failed numerically (stopped on <reason>[, non-finite cost])" followed by
/// "; no value of the data stands out: ..." or ": the data hold values ...", one line per extreme
/// value of `train` and a hint that depends on `outlier_rejection`; every line ends in "\n".
std::string FitFailureText(const std::string& data, const IdentificationRun& run, const JointSamples& train,
                           bool outlier_rejection);

}  // namespace inertial
