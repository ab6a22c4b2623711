/// @file closed_form_bodies.hpp
/// Solid homogeneous bodies with textbook inertias, placed anywhere: for tests and examples.
///
/// Each factory takes the body's mass [kg] and dimensions [m] in its own frame C (centred at the
/// centroid, axes along its symmetry axes), and a pose of C in the body frame B: rotation R_BC and
/// position p_BoCo_B. The result is pi about Bo, expressed in B (conventions of
/// inertial_params.hpp). Second moments about the centroid along C's axes (integral of x^2 rho):
///   box with sides a, b, c:              L = m/12 [a^2, b^2, c^2]
///   cylinder, radius r, length l (on z): L = m [r^2/4, r^2/4, l^2/12]
///   sphere, radius r:                    L = m r^2/5 [1, 1, 1]
///   ellipsoid, semi-axes a, b, c:        L = m/5 [a^2, b^2, c^2]
/// and the principal moments are D = [Ly + Lz, Lx + Lz, Lx + Ly] (eq. 5).
/// @throws std::invalid_argument if the mass or a dimension is not positive and finite.
#pragma once

#include "inertial/inertia/inertial_params.hpp"

namespace inertial {

/// Pose of a body's own frame C in B.
struct Pose {
  Matrix3 R_BC = Matrix3::Identity();
  Vector3 p_BoCo_B = Vector3::Zero();
};

InertialParams SolidBox(double mass, double size_x, double size_y, double size_z, const Pose& pose = Pose());
InertialParams SolidCylinder(double mass, double radius, double length, const Pose& pose = Pose());
InertialParams SolidSphere(double mass, double radius, const Pose& pose = Pose());
InertialParams SolidEllipsoid(double mass, double semi_axis_x, double semi_axis_y, double semi_axis_z,
                              const Pose& pose = Pose());

/// A body with the given mass and second moments L about its centroid along C's axes [kg m^2]:
/// the common core of the factories above. L must be > 0 for a fully consistent body.
InertialParams BodyFromSecondMoments(double mass, const Vector3& L, const Pose& pose = Pose());

}  // namespace inertial
