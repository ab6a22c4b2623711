/// @file robust_statistics.hpp
/// Median and median absolute deviation (MAD), the location and scale that a few glitched values
/// cannot move (breakdown point 50 %). For Gaussian data, kMadToSigma MAD estimates the standard
/// deviation (1 / Phi^-1(3/4) = 1.4826).
#pragma once

#include <utility>
#include <vector>

namespace inertial {

inline constexpr double kMadToSigma = 1.4826;

/// Median of v (v is reordered); the mean of the two middle values for an even count, computed
/// without overflow for huge values of opposite sign. @throws std::invalid_argument if v is empty.
double Median(std::vector<double>& v);

/// {median, MAD} of v (v is overwritten with the absolute deviations). @throws as Median.
std::pair<double, double> MedianAndMad(std::vector<double>& v);

}  // namespace inertial
