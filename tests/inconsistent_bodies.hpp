/// @file inconsistent_bodies.hpp
/// A shared set of bodies that are not fully physically consistent, for the tests of every inverse
/// map (each must refuse all of them): negative and zero mass, a plate, a rod, a violated triangle
/// inequality, 500 plates in general position (zero only up to rounding), NaN and Inf.
#pragma once

#include <limits>
#include <vector>

#include "inertial/inertia/closed_form_bodies.hpp"
#include "test_support.hpp"

namespace inertial::testing {

inline std::vector<Vector10> InconsistentBodies(unsigned seed) {
  Rng rng(seed);
  std::vector<Vector10> bodies;
  const Vector10 box = SolidBox(1.0, 0.1, 0.2, 0.3).vector();
  Vector10 negative_mass = box;
  negative_mass[pi_index::kMass] = -1.0;
  bodies.push_back(negative_mass);
  Vector10 zero_mass = box;
  zero_mass[pi_index::kMass] = 0.0;
  bodies.push_back(zero_mass);
  bodies.push_back(BodyFromSecondMoments(1.0, Vector3(0.1, 0.2, 0.0)).vector());    // plate, Lz = 0
  bodies.push_back(BodyFromSecondMoments(1.0, Vector3(0.1, 0.0, 0.0)).vector());    // rod
  bodies.push_back(BodyFromSecondMoments(1.0, Vector3(0.1, 0.2, -0.05)).vector());  // triangle violated
  for (int n = 0; n < 500; ++n) {  // plates in general position (L = 0 only up to rounding)
    const Pose pose = rng.RandomPose<Pose>(2.0);
    // One draw per statement, in the order the x86-64 build drew them (see testing::Rng).
    const double Ly = rng.Uniform(0.01, 1.0);
    const double Lx = rng.Uniform(0.01, 1.0);
    const double mass = rng.Uniform(0.1, 10.0);
    bodies.push_back(BodyFromSecondMoments(mass, Vector3(Lx, Ly, 0.0), pose).vector());
  }
  Vector10 nan = box;
  nan[pi_index::kIxy] = std::numeric_limits<double>::quiet_NaN();
  bodies.push_back(nan);
  Vector10 inf = box;
  inf[pi_index::kHx] = std::numeric_limits<double>::infinity();
  bodies.push_back(inf);
  return bodies;
}

}  // namespace inertial::testing
