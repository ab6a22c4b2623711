/// @file body_stream.hpp
/// Test helper: a simulated single-body stream (a rotated box on a force/torque sensor moving with a
/// multi-sine twist, gravity turning in the body frame) and the prior the estimators start from.
#pragma once

#include <cmath>
#include <vector>

#include <Eigen/Geometry>

#include "inertial/estimation/online/online_body_estimator.hpp"
#include "inertial/inertia/closed_form_bodies.hpp"
#include "inertial/model/rigid_body_regressor.hpp"
#include "test_support.hpp"

namespace inertial::testing {

// The truth: a 1.3 kg box, 0.2 x 0.1 x 0.05 m, rotated, its centre 8 cm from the sensor frame.
inline InertialParams TrueBody() {
  Pose pose;
  pose.R_BC = Eigen::AngleAxisd(0.4, Vector3(1, 2, 3).normalized()).toRotationMatrix();
  pose.p_BoCo_B = Vector3(0.05, -0.03, 0.06);
  return SolidBox(1.3, 0.2, 0.1, 0.05, pose);
}

// The prior the estimators start from: a 1 kg sphere of radius 5 cm at the origin.
inline InertialParams Prior() { return SolidSphere(1.0, 0.05); }

// A stream at `rate` Hz: the sensor frame moves with a multi-sine twist (rad/s, m/s), gravity
// rotates in the body frame; the wrench w = Y(xi, xi_dot, g) pi_true exactly, plus Gaussian noise.
inline std::vector<BodySample> Stream(const InertialParams& body, double seconds, double rate, double sigma, unsigned seed,
                                      double t0 = 0.0) {
  Rng rng(seed);
  std::vector<BodySample> out;
  const int N = static_cast<int>(seconds * rate);
  for (int k = 0; k < N; ++k) {
    const double t = t0 + k / rate;
    BodySample s;
    s.t = t;
    for (int i = 0; i < 6; ++i) {
      const double f = 0.3 + 0.17 * i;
      s.twist[i] = (i < 3 ? 2.0 : 0.5) * std::sin(2 * M_PI * f * t + i);
      s.acceleration[i] = (i < 3 ? 2.0 : 0.5) * 2 * M_PI * f * std::cos(2 * M_PI * f * t + i);
    }
    s.has_acceleration = true;
    s.gravity = 9.81 * Vector3(std::sin(0.7 * t), std::cos(0.7 * t) * std::sin(0.3 * t), -std::cos(0.3 * t)).normalized();
    s.wrench = RigidBodyRegressor(s.twist, s.acceleration, s.gravity) * body.vector();
    for (int i = 0; i < 6; ++i) s.wrench[i] += rng.Normal(sigma);
    out.push_back(s);
  }
  return out;
}

}  // namespace inertial::testing
