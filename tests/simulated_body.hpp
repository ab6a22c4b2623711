/// @file simulated_body.hpp
/// Test helper: single-body logs of a free body under the paper's wrench (Section VI,
/// w_k(t) = sin(t + k pi / 3)), simulated from rest by the project's integrator, with sensor errors
/// added by the caller.
#pragma once

#include <cmath>
#include <functional>
#include <stdexcept>
#include <vector>

#include "inertial/model/body_effect_model.hpp"
#include "inertial/model/rigid_body_simulation.hpp"
#include "test_support.hpp"

namespace inertial::testing {

/// A body of 0.7 kg with an off-origin COM and a full inertia tensor.
inline InertialParams TestFreeBody() {
  return InertialParams::FromMassComInertia(
      0.7, Vector3(0.1, -0.2, 0.05), (Matrix3() << 0.3, 0.02, -0.01, 0.02, 0.25, 0.03, -0.01, 0.03, 0.4).finished());
}

/// `seconds` of `body` at `rate` Hz; `corrupt` adds the sensor's errors to each sample, drawing from
/// one Rng seeded with `seed`. @throws std::runtime_error if the integration fails.
inline BodyLog SimulateFreeBody(const InertialParams& body, double rate, double seconds, unsigned seed,
                                const std::function<void(TwistWrenchSample*, Rng*)>& corrupt) {
  std::vector<double> times;
  for (int i = 0; i <= static_cast<int>(std::lround(seconds * rate)); ++i) times.push_back(i / rate);
  auto wrench = [](double t) {
    Vector6 w;
    for (int k = 0; k < 6; ++k) w[k] = std::sin(t + k * M_PI / 3);
    return w;
  };
  const SimulationResult sim = SimulateRigidBody(body, Vector6::Zero(), wrench, times);
  if (!sim.ok) throw std::runtime_error("SimulateFreeBody: the integration failed");
  Rng rng(seed);
  BodyLog log;
  for (size_t i = 0; i < times.size(); ++i) {
    TwistWrenchSample s;
    s.t = times[i];
    s.twist = sim.twists[i];
    s.wrench = wrench(times[i]);
    corrupt(&s, &rng);
    log.samples.push_back(s);
  }
  return log;
}

}  // namespace inertial::testing
