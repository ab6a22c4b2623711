/// @file sample_times.hpp
/// Test helper: sample times 0, dt, 2 dt, ... up to `end`.
#pragma once

#include <vector>

namespace inertial::testing {

inline std::vector<double> Times(double dt, double end) {
  std::vector<double> t;
  for (int k = 0; k * dt <= end + 1e-12; ++k) t.push_back(k * dt);
  return t;
}

}  // namespace inertial::testing
