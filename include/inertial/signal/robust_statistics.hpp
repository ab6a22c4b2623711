/// @file robust_statistics.hpp
/// Median and median absolute deviation (MAD), the location and scale that a few glitched values
/// cannot move (breakdown point 50 %). For Gaussian data, kMadToSigma MAD estimates the standard
/// deviation (1 / Phi^-1(3/4) = 1.4826).
#pragma once

#include <Eigen/Core>

#include <utility>
#include <vector>

namespace inertial {

inline constexpr double kMadToSigma = 1.4826;

/// Median of v (v is reordered); the mean of the two middle values for an even count, computed
/// without overflow for huge values of opposite sign. @throws std::invalid_argument if v is empty.
double Median(std::vector<double>& v);

/// Median of the steps t[i + 1] - t[i] of time stamps (at least 2). @throws std::invalid_argument
/// with fewer.
double MedianStep(const Eigen::Ref<const Eigen::VectorXd>& t);

/// {median, MAD} of v (v is overwritten with the absolute deviations). @throws as Median.
std::pair<double, double> MedianAndMad(std::vector<double>& v);

/// The threshold k for n residuals (robust_identification.hpp, sample_glitches.hpp): a Chauvenet-style bound, for heavy tails. For
/// n = rows x joints Gaussian residuals, P(|Z| > k) = 0.01 / n, i.e. k = Phi^-1(1 - 0.005 / n),
/// makes the expected number of good residuals wrongly rejected 0.01 over the whole log (never
/// below 5). Real residuals are heavier-tailed than that (unmodelled friction transitions, cable
/// forces, impacts): on the KUKA LWR4+ measurements the Gaussian bound (5.13) left out 170 of
/// 5027 rows, good data the model merely explains less well. So the bound is taken for Laplace
/// residuals instead, whose tail beyond k robust standard deviations (1.4826 MAD = 1.028 b for
/// scale b) is exp(-1.028 k): 0.01 expected wrongly rejected residuals gives
/// k = ln(100 n) / 1.028, 14.5 for the leg's 30 000 residuals, 14.7 for the KUKA's 35 000 (none
/// left out there). A glitch (1e6 N m, a saturation code, a counter read as a float) is hundreds or
/// millions of robust scales out, far beyond either bound; what this threshold lets through are
/// moderate errors, which bend a least-squares fit of thousands of rows only a little.
///
/// The Gaussian threshold for n residuals: max(5, Phi^-1(1 - 0.005 / n)).
/// @throws std::invalid_argument if n < 1.
double ChauvenetThreshold(long long n);
/// The same for Laplace (heavy-tailed) residuals: ln(100 n) / (1.4826 ln 2).
/// @throws std::invalid_argument if n < 1.
double HeavyTailThreshold(long long n);
/// The default k (OutlierOptions::threshold = 0): max(ChauvenetThreshold(n), HeavyTailThreshold(n)).
double DefaultOutlierThreshold(long long n);

}  // namespace inertial
