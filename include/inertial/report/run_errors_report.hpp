/// @file run_errors_report.hpp
/// A model's errors run by run when several recorded runs were fitted as one (identify, validate and
/// diagnose with --data given more than once): one line per run, and the same as JSON
/// [{run, samples, rms {joint..., total}, relative_rms {joint..., total}}].
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "inertial/diagnosis/model_comparison.hpp"

namespace inertial {

/// "<what>, run by run:\n  a.csv (1200 samples): RMS 0.31 N m (2.1 %); worst knee 0.52 N m\n ...";
/// empty for a single run (its figures are the pooled ones).
std::string RunErrorsText(const std::vector<std::string>& names, const std::vector<ModelComparison>& runs,
                          const std::string& what);
nlohmann::json RunErrorsJson(const std::vector<std::string>& names, const std::vector<ModelComparison>& runs);

}  // namespace inertial
