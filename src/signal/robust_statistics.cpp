#include "inertial/signal/robust_statistics.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace inertial {
namespace {

constexpr double kMinimumThreshold = 5.0;          // k never below this (header)
constexpr double kExpectedFalseRejections = 0.01;  // good residuals wrongly rejected over the whole log

}  // namespace

double MedianStep(const Eigen::Ref<const Eigen::VectorXd>& t) {
  if (t.size() < 2) throw std::invalid_argument("MedianStep: fewer than 2 time stamps");
  std::vector<double> steps(static_cast<std::size_t>(t.size() - 1));
  for (Eigen::Index i = 0; i + 1 < t.size(); ++i) steps[static_cast<std::size_t>(i)] = t[i + 1] - t[i];
  return Median(steps);
}

double Median(std::vector<double>& v) {
  if (v.empty()) throw std::invalid_argument("Median: no values");
  const std::size_t half = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(half), v.end());
  const double upper = v[half];
  if (v.size() % 2 == 1) return upper;
  const double lower = *std::max_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(half));
  return 0.5 * lower + 0.5 * upper;  // halves first: no overflow for huge values of opposite sign
}

std::pair<double, double> MedianAndMad(std::vector<double>& v) {
  const double median = Median(v);
  for (double& x : v) x = std::abs(x - median);
  return {median, Median(v)};
}

double ChauvenetThreshold(long long n) {
  if (n < 1) throw std::invalid_argument("ChauvenetThreshold: the number of residuals must be at least 1");
  // Two-sided: P(|Z| > k) = 0.01 / n, i.e. the upper tail 0.5 erfc(k / sqrt 2) = 0.005 / n. Bisection
  // (the tail is monotone); erfc stays accurate down to 1e-308 (k about 37.5), far beyond any n.
  const double tail = 0.5 * kExpectedFalseRejections / static_cast<double>(n);
  double lo = 0.0, hi = 40.0;
  for (int iteration = 0; iteration < 200 && hi - lo > 1e-12; ++iteration) {
    const double mid = 0.5 * (lo + hi);
    (0.5 * std::erfc(mid / std::sqrt(2.0)) > tail ? lo : hi) = mid;
  }
  return std::max(kMinimumThreshold, 0.5 * (lo + hi));
}

double HeavyTailThreshold(long long n) {
  if (n < 1) throw std::invalid_argument("HeavyTailThreshold: the number of residuals must be at least 1");
  // Laplace residuals of scale b: MAD = b ln 2, robust sd s = 1.4826 b ln 2, and
  // P(|r| > k s) = exp(-k 1.4826 ln 2). Expected wrongly rejected residuals n P = 0.01 gives k.
  const double rate = 1.4826 * std::log(2.0);
  return std::log(static_cast<double>(n) / kExpectedFalseRejections) / rate;
}

double DefaultOutlierThreshold(long long n) { return std::max(ChauvenetThreshold(n), HeavyTailThreshold(n)); }

}  // namespace inertial
