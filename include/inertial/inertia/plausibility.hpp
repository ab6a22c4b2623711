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
/// The divergence weighs every direction of the mass distribution alike, including the thin ones: a
/// 1 cm COM shift across a 3 cm thick link changes J along that direction by a factor of several,
/// although it is an ordinary CAD error. The tolerance is therefore stated in the physical words:
///   factor = max(max(m/m0, m0/m), 1 + |m (c - c0)| / (m0 rho0), 1 + ||I_c - I_c0|| / ||I_c0||),
/// rho0 = sqrt(tr(Sigma0) / m0) the prior's RMS radius of its mass about its COM (its size), I_c the
/// rotational inertia about the COM and ||.|| the spectral norm. The middle term is the first moment
/// of the body about the prior's COM, relative to the prior's own scale m0 rho0: the data fix it
/// (gravity torques) where they fix neither mass nor COM alone, and a payload m_p at distance r from
/// the link's COM gives exactly m_p r. A body scaled by s has factor max(s, 1/s); a payload as
/// heavy as its link at least 2.
///
/// Tolerance. A URDF's inertia comes from CAD: masses typically 10-30 % off (cables, fasteners,
/// paint, wrong densities), COMs off by centimetres (a fraction of the link's size), moments by up
/// to half: factors up to about 1.5. kDefaultPriorTolerance = 0.75 (within a factor 1.75) leaves
/// that ordinary error inside with margin; a payload as heavy as its link (factor >= 2, more when
/// it sits away from the link's COM) or a link imitating a rotor's inertia (a leg's thigh
/// identified at 6 times its mass) lies outside.
/// Noise. An estimate strays from its prior by its own uncertainty too; a departure counts only
/// where the data establish it. With margins (e.g. 3 standard deviations of the estimate, from
/// fit_uncertainty.hpp), every departure is first shrunk toward the prior by its margin: the mass
/// toward m0, the COM shift's length by the margin along its direction, each entry of I_c - I_c0 toward
/// zero; the factor is that of what remains (raw_factor: without margins).
#pragma once

#include "inertial/inertia/inertial_params.hpp"

namespace inertial {

/// A body is within tolerance t of its prior when its departure factor is at most 1 + t.
inline constexpr double kDefaultPriorTolerance = 0.75;

/// Margins of the departures (see the file comment): mass [kg]; the first moment about the prior's
/// COM as a 3x3 matrix whose square root along a direction is the margin along it (z^2 times its
/// covariance) [kg^2 m^2]; inertia about the COM per entry in the order Ixx Iyy Izz Ixy Iyz Ixz
/// [kg m^2]. Non-negative; +infinity allowed (an undetermined quantity counts no departure).
struct DepartureMargins {
  double mass = 0.0;
  Matrix3 first_moment = Matrix3::Zero();
  Vector6 inertia_about_com = Vector6::Zero();
};

struct BodyPlausibility {
  double mass_ratio = 1.0;          ///< m / m0
  double com_shift = 0.0;           ///< |c - c0| [m], in the frame both are expressed in
  double com_shift_relative = 0.0;  ///< |c - c0| / rho0 (see the file comment)
  double first_moment_change = 0.0; ///< |m (c - c0)| / (m0 rho0)
  double inertia_change = 0.0;      ///< ||I_c - I_c0|| / ||I_c0|| (spectral norms)
  Vector3 moment_ratios = Vector3::Ones();  ///< principal moments about the COM, sorted, over the prior's
  Vector4 lambda = Vector4::Ones();  ///< generalized eigenvalues of (J, J0), ascending
  double divergence = 0.0;          ///< d(J || J0), eq. 14
  double factor = 1.0;              ///< the departure factor beyond the margins (see the file comment), >= 1
  double raw_factor = 1.0;          ///< the departure factor of the estimate itself

  /// Whether factor <= 1 + tolerance.
  bool Within(double tolerance) const { return factor <= 1.0 + tolerance; }
  /// log(factor) - log(1 + tolerance), floored at 0: how far outside the tolerance, scale-free.
  double Excess(double tolerance) const;
};

/// @throws std::invalid_argument if either body's pseudo-inertia is not positive definite (a body
/// that is not fully physically consistent has no plausibility to measure).
BodyPlausibility MeasurePlausibility(const InertialParams& body, const InertialParams& prior,
                                     const DepartureMargins& margins = {});

}  // namespace inertial
