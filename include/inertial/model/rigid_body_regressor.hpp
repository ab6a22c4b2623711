/// @file rigid_body_regressor.hpp
/// The Newton-Euler equations of one rigid body in body coordinates (Rucker & Wensing 2022,
/// eq. 12) written linearly in pi:
///
///   I xi_dot + xi x* I xi - w_gravity = Y(xi, xi_dot, g) pi,
///
/// where I is the 6x6 spatial inertia at the body-frame origin (eq. 2), xi = [omega; v] the body
/// twist (v: velocity of the frame origin), xi_dot its time derivative in body coordinates, and
/// w_gravity = [h x g; m g] the gravity wrench for a gravity vector g_B expressed in the body frame
/// (zero for the paper's free body). The result is the wrench [moment about Bo; force] that the
/// environment (e.g. a force/torque sensor) must apply. Gravity enters exactly as an extra linear
/// acceleration -g of the frame, so Y(xi, xi_dot, g) = Y(xi, xi_dot - [0; g], 0).
///
/// Conventions: pi order as in types.hpp; spatial vectors angular first; SI units.
#pragma once

#include "inertial/inertia/types.hpp"

namespace inertial {

/// Y (6x10) with w = Y pi. Allocation-free.
Matrix6x10 RigidBodyRegressor(const Vector6& xi, const Vector6& xi_dot, const Vector3& g_B = Vector3::Zero());

/// The 3x6 map L(x) with I x = L(x) [Ixx, Iyy, Izz, Ixy, Iyz, Ixz] for a symmetric 3x3 I.
Eigen::Matrix<double, 3, 6> InertiaTimesVectorMap(const Vector3& x);

}  // namespace inertial
