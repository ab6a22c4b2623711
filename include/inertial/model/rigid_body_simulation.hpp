/// @file rigid_body_simulation.hpp
/// Forward dynamics of one free rigid body in body coordinates (eq. 12 solved for xi_dot):
///   xi_dot = I^{-1} (w(t) - xi x* I xi),
/// integrated with the embedded Dormand-Prince 5(4) Runge-Kutta pair (Dormand & Prince 1980;
/// coefficients as tabulated in Hairer, Norsett & Wanner, Solving ODEs I, Table 5.2) with adaptive
/// steps, landing exactly on every requested sample time.
/// Conventions: twist [omega; v], wrench [moment; force] in body coordinates, at the frame origin.
#pragma once

#include <functional>
#include <vector>

#include "inertial/inertia/inertial_params.hpp"

namespace inertial {

struct IntegratorOptions {
  double relative_tolerance = 1e-10;  ///< per-component error bound relative to |xi|
  double absolute_tolerance = 1e-12;  ///< per-component absolute error bound
  double initial_step = 1e-3;         ///< [s]
  int max_steps = 1000000;
};

struct SimulationResult {
  std::vector<Vector6> twists;  ///< one per sample time
  int accepted_steps = 0;
  int rejected_steps = 0;
  bool ok = false;  ///< false if max_steps was hit or the state became non-finite
};

/// Integrates from xi(sample_times[0]) = xi0 and returns xi at every sample time (ascending).
/// Precondition: the body's spatial inertia is invertible (m > 0, consistent).
SimulationResult SimulateRigidBody(const InertialParams& body, const Vector6& xi0,
                                   const std::function<Vector6(double)>& wrench,
                                   const std::vector<double>& sample_times,
                                   const IntegratorOptions& options = IntegratorOptions());

/// Kinetic energy 0.5 xi^T I xi [J].
double KineticEnergy(const InertialParams& body, const Vector6& xi);

}  // namespace inertial
