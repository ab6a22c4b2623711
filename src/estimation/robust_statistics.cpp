#include "inertial/estimation/robust_statistics.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace inertial {

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

}  // namespace inertial
