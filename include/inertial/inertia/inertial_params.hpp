/// @file inertial_params.hpp
/// InertialParams: the ten classical inertial parameters pi of one rigid body, and their
/// conversions to mass / center of mass / rotational inertia, the 6x6 spatial inertia (eq. 2), the
/// 4x4 pseudo-inertia J (Section IV, eq. 6) and to another frame.
///
/// Conventions: pi = [m, hx, hy, hz, Ixx, Iyy, Izz, Ixy, Iyz, Ixz] (Rucker & Wensing 2022, eq. 3);
/// h = m c; rotational inertia about the origin Bo of the body frame B, expressed in B; Ixy is the
/// (0,1) tensor entry (= -integral of x y rho). Spatial vectors angular first. SI units.
/// Monogram names: p_BoBcm_B = position of the COM from Bo in B; I_Bo_B = rotational inertia about
/// Bo in B; I_Bcm_B = about the COM.
///
/// An InertialParams may hold any ten numbers, physically consistent or not (a linear least-squares
/// estimate often is not): consistency is asked of CheckConsistency() (consistency.hpp).
#pragma once

#include "inertial/inertia/types.hpp"

namespace inertial {

class InertialParams {
 public:
  /// The zero body (m = 0): a placeholder, not a physical body.
  InertialParams() : pi_(Vector10::Zero()) {}

  /// From pi in the order above. No checks: any ten numbers are representable.
  static InertialParams FromVector(const Vector10& pi) { return InertialParams(pi); }

  /// From mass m [kg], first mass moment h_B = m p_BoBcm_B [kg m] and rotational inertia about Bo.
  /// Only the symmetric part of I_Bo_B is used.
  static InertialParams FromMassFirstMomentInertia(double m, const Vector3& h_B, const Matrix3& I_Bo_B);

  /// From mass, center of mass and rotational inertia about the COM (parallel-axis theorem:
  /// I_Bo = I_Bcm + m (|c|^2 1 - c c^T)).
  static InertialParams FromMassComInertia(double m, const Vector3& p_BoBcm_B, const Matrix3& I_Bcm_B);

  /// From the 6x6 spatial inertia [[I_Bo_B, S(h)], [S(h)^T, m 1]] (eq. 2).
  /// @throws std::invalid_argument if M is not of that form (asymmetric, lower-right block not
  /// m times identity, off-diagonal blocks not S(h) and S(h)^T), within `tolerance` (absolute).
  static InertialParams FromSpatialInertia(const Matrix6& M, double tolerance = 1e-9);

  /// From the pseudo-inertia J = [[Sigma, h], [h^T, m]] with Sigma = tr(I)/2 1 - I (Section IV).
  /// @throws std::invalid_argument if J is not symmetric within `tolerance` (absolute).
  static InertialParams FromPseudoInertia(const Matrix4& J, double tolerance = 1e-9);

  const Vector10& vector() const { return pi_; }
  double mass() const { return pi_[pi_index::kMass]; }
  /// h = m c [kg m].
  Vector3 first_moment() const { return pi_.segment<3>(pi_index::kHx); }
  /// c = h / m [m]. Precondition: mass() != 0.
  Vector3 com() const { return first_moment() / mass(); }
  /// I_Bo_B [kg m^2], symmetric.
  Matrix3 rotational_inertia_about_origin() const;
  /// I_Bcm_B [kg m^2]. Precondition: mass() != 0.
  Matrix3 rotational_inertia_about_com() const;
  /// The 6x6 spatial inertia at Bo (eq. 2), angular rows/columns first.
  Matrix6 spatial_inertia() const;
  /// The 4x4 pseudo-inertia J (Section IV; J = integral of q q^T rho, q = [x; 1], eq. 6).
  Matrix4 pseudo_inertia() const;
  /// Sigma = tr(I_Bo)/2 1 - I_Bo: the second moments of mass about Bo (integral of x x^T rho).
  Matrix3 second_moments_about_origin() const;

  /// The same body expressed in frame A, where a point x_B of the body sits at
  /// x_A = R_AB x_B + p_AoBo_A. Exact (J_A = T J_B T^T with T = [[R_AB, p_AoBo_A], [0, 1]]).
  /// Precondition: R_AB is a rotation.
  InertialParams Transformed(const Matrix3& R_AB, const Vector3& p_AoBo_A) const;

  /// Sum of two bodies rigidly joined and expressed in the same frame (pi is additive).
  InertialParams operator+(const InertialParams& other) const { return InertialParams(pi_ + other.pi_); }

  bool AllFinite() const { return pi_.allFinite(); }

 private:
  explicit InertialParams(const Vector10& pi) : pi_(pi) {}
  Vector10 pi_;
};

/// The linear map J(pi) as a function on vectors: pseudo-inertia from pi and back.
Matrix4 PseudoInertiaFromPi(const Vector10& pi);
/// pi from the symmetric part of J.
Vector10 PiFromPseudoInertia(const Matrix4& J);
/// The adjoint of PiFromPseudoInertia: the symmetric G with g . PiFromPseudoInertia(J) = tr(G J)
/// for every symmetric J (the gradient of a function of pi, as a gradient in J). From m = J33,
/// h = J(0:3, 3), Ixx = S11 + S22, ..., Ixy = -S01, ... (S = J(0:3, 0:3)):
///   G33 = g_m, G(k, 3) = g_hk / 2, G00 = g_Iyy + g_Izz, G11 = g_Ixx + g_Izz, G22 = g_Ixx + g_Iyy,
///   G01 = -g_Ixy / 2, G12 = -g_Iyz / 2, G02 = -g_Ixz / 2.
Matrix4 PseudoInertiaGradient(const Vector10& g);

}  // namespace inertial
