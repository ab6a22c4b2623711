/// @file plausibility.hpp
/// How far an identified body is from its prior (a URDF's CAD inertia), in physical words and as
/// one scale-free number a tolerance can be stated in.
///
/// Physical words: mass ratio m / m0, COM shift |c - c0|, and the ratios of the principal moments
/// about the COM (each sorted ascending, identified over prior).
///
/// One number. With J and J0 the pseudo-inertias (eq. 5), the generalized eigenvalues lambda_i of
/// J v = lambda J0 v (i = 1..4) say by which factor the body departs from its prior along every
/// direction of its mass distribution at once: the second moment of the identified body along any
/// (affine) direction u, u^T J u, lies between lambda_min and lambda_max times the prior's. They
/// are invariant under any change of coordinates applied to both bodies (as the divergence is), and
///   d(J || J0) = sum_i (lambda_i - 1 - log lambda_i)        (eq. 14's log-det divergence).
/// The departure factor is max_i max(lambda_i, 1 / lambda_i) >= 1: a body scaled by s has factor s;
/// a point mass m0 at the prior's COM doubled has 2; a payload of mass m_p at a distance r from the
/// link's COM gives at least 1 + (m_p / m0)(1 + r^2 / rho^2), rho the link's radius of gyration
/// along r (the Schur complement of J0).
///
/// Tolerance. A URDF's inertia comes from CAD: masses typically 10-30 % off (cables, fasteners,
/// paint, wrong densities), COMs off by centimetres, moments by more. kDefaultPriorTolerance = 1
/// (the identified body within a factor 2 of the prior along every direction) leaves that ordinary
/// error inside, with room for the factors combining; a payload as heavy as its link (factor >= 2,
/// more when it sits away from the link's COM) or a link imitating a rotor's inertia lies outside.
#pragma once

#include "inertial/inertia/inertial_params.hpp"

namespace inertial {

/// A body is within tolerance t of its prior when its departure factor is at most 1 + t.
inline constexpr double kDefaultPriorTolerance = 1.0;

struct BodyPlausibility {
  double mass_ratio = 1.0;          ///< m / m0
  double com_shift = 0.0;           ///< |c - c0| [m], in the frame both are expressed in
  Vector3 moment_ratios = Vector3::Ones();  ///< principal moments about the COM, sorted, over the prior's
  Vector4 lambda = Vector4::Ones();  ///< generalized eigenvalues of (J, J0), ascending
  double divergence = 0.0;          ///< d(J || J0), eq. 14
  double factor = 1.0;              ///< max_i max(lambda_i, 1 / lambda_i)

  /// Whether factor <= 1 + tolerance.
  bool Within(double tolerance) const { return factor <= 1.0 + tolerance; }
  /// log(factor) - log(1 + tolerance), floored at 0: how far outside the tolerance, scale-free.
  double Excess(double tolerance) const;
};

/// @throws std::invalid_argument if either body's pseudo-inertia is not positive definite (a body
/// that is not fully physically consistent has no plausibility to measure).
BodyPlausibility MeasurePlausibility(const InertialParams& body, const InertialParams& prior);

}  // namespace inertial
