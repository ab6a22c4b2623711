/// @file body_sample.hpp
/// One single-body sample as an online source delivers it (a payload on a force/torque sensor, a
/// link with a wrench sensor): time, twist, optionally its derivative, the applied wrench and
/// gravity, all in the body frame. Spatial vectors angular first; SI units.
#pragma once

#include "inertial/inertia/types.hpp"

namespace inertial {

struct BodySample {
  double t = 0.0;
  Vector6 twist = Vector6::Zero();         ///< [omega; v] in the body frame [rad/s, m/s]
  bool has_acceleration = false;
  Vector6 acceleration = Vector6::Zero();  ///< d(twist)/dt in body coordinates
  Vector6 wrench = Vector6::Zero();        ///< [moment about the frame origin; force] [N m, N]
  Vector3 gravity = Vector3::Zero();       ///< g in the body frame [m/s^2] (zero: a free body)
};

}  // namespace inertial
