/// @file study_report.hpp
/// Output of `inertial study`: the side-by-side table (this run vs. the paper's Section VI),
/// the JSON document, and the --report directory with a Fig. 1-like histogram drawn by gnuplot.
#pragma once

#include <algorithm>
#include <nlohmann/json.hpp>
#include <string>

#include "inertial/study/paper_study.hpp"

namespace inertial {

/// The paper's reported figures (Rucker & Wensing 2022, Section VI-B), for comparison.
struct PaperStudyFigures {
  static constexpr int kBodies = 1000;
  static constexpr int kNonphysical = 151;
  static constexpr int kNegativeMass = 0;
  static constexpr int kNotPositiveDefinite = 42;
  static constexpr double kMeanMostNegativeEigenvalue = -0.04;  // kg m^2
  static constexpr int kTriangleViolations = 151;               // "all of the nonphysical cases"
  static constexpr double kMeanTriangleViolation = -0.09;       // kg m^2
  static constexpr double kSecondsPerIteration = 0.02;          // Matlab lsqnonlin, all methods
};

/// The iteration histogram of the figure and table has kHistogramBins bins of equal width covering
/// 1..max_iterations (1-5, 6-10, ..., 46-50 for the paper's cap of 50), then a "failed" bin.
inline constexpr int kHistogramBins = 10;
inline int HistogramBinWidth(int max_iterations) { return std::max(1, (max_iterations + kHistogramBins - 1) / kHistogramBins); }

/// Plain-text table: this run beside the paper.
std::string StudyTable(const StudyResult& result);

/// The JSON document of --json. Keys: bodies, seed, settings, linear_ls {nonphysical,
/// negative_mass, not_positive_definite, not_positive_definite_com, triangle_violations,
/// mean_most_negative_eigenvalue, mean_triangle_violation, median_parameter_error},
/// methods.{linear,eigenvalue,exponential,log_cholesky} {iterations[], failures,
/// max_iteration_stops, numerical_failures, inconsistent_results, seconds_per_iteration,
/// median_iterations, median_parameter_error, mean_parameter_error}, paper {...}, wall_seconds.
nlohmann::json StudyToJson(const StudyResult& result);

/// Writes DIR/study.json, DIR/table.txt, DIR/iterations.dat, DIR/fig1.gp and DIR/fig1.png (by
/// running gnuplot on fig1.gp). Creates DIR if needed.
/// @throws std::runtime_error naming the file or command that failed.
void WriteStudyReport(const StudyResult& result, const std::string& directory);

}  // namespace inertial
