/// @file eigenvalue_parameterization.hpp
/// The eigenvalue (principal-axes) parameterization of rigid-body inertia (Rucker & Wensing 2022,
/// Section III), with the rotation in exponential coordinates.
///
/// phi = [m, cx, cy, cz, beta1, beta2, beta3, Lx, Ly, Lz] (Section III-A):
///   m     mass [kg], used as it is (not exponentiated);
///   c     center of mass in the body frame B [m];
///   beta  exponential coordinates [rad] of the rotation R = exp(S(beta)) whose columns are the
///         principal axes, expressed in B;
///   L     second moments of mass about the COM along the principal axes [kg m^2] (eq. 5), used
///         as they are (not exponentiated).
/// and pi follows from
///   D = diag(Ly + Lz, Lx + Lz, Lx + Ly)                        (eq. 5)
///   I_Bcm_B = R D R^T,   I_Bo_B = I_Bcm_B + m (|c|^2 1 - c c^T),   h = m c.
/// Equivalently Sigma_Bcm_B = R diag(L) R^T: the pseudo-inertia's second-moment block about the COM.
///
/// The body is fully physically consistent iff m > 0 and all L > 0 (Theorem II.1 with eq. 5); ToPi
/// accepts any phi (negative m or L give a finite, inconsistent pi). The map is neither one-to-one
/// (the L may be permuted along with the columns of R, and beta is 2 pi periodic along its axis)
/// nor a local diffeomorphism everywhere: its Jacobian determinant is (derived below)
///
///   det(J_pi_phi) = -4 m^3 (1 - cos|beta|) / |beta|^2 (Lx - Ly)(Ly - Lz)(Lx - Lz),
///
/// so it vanishes whenever two second moments are equal (Section III-A: a body with rotational
/// symmetry of order >= 3, e.g. a cylinder), whatever the rotation, and also at |beta| = 2 pi k,
/// k >= 1 (a singularity of exponential coordinates only). Derivation: pi is a linear function of
/// the pseudo-inertia J = [[Sigma_Bcm_B + m c c^T, m c], [m c^T, m]] with determinant -2 (taking
/// the J entries in pi's slot order); (m, c, Sigma_Bcm_B) -> (m, h, Sigma_Bo_B) is block triangular
/// with determinant m^3; and dSigma_Bcm_B = R (dLambda + S(w) Lambda - Lambda S(w)) R^T, with
/// Lambda = diag(L) and w = R^T J_l(beta) dbeta, whose off-diagonal entries (01, 12, 02) are
/// w_z (Lx - Ly), w_x (Ly - Lz), w_y (Lz - Lx): the factors (Lx - Ly)(Ly - Lz)(Lx - Lz) times
/// det(J_l) = 2 (1 - cos|beta|)/|beta|^2 (X -> R X R^T on symmetric matrices has determinant
/// det(R)^4 = 1).
///
/// Rotation conventions: R = exp(S(beta)) maps principal-axes coordinates to B (R x~ = x, Section
/// II). Its derivative is dR/dbeta_k = S(J_l(beta) e_k) R with the left Jacobian of SO(3)
///   J_l(beta) = 1 + (1 - cos t)/t^2 S(beta) + (t - sin t)/t^3 S(beta)^2,   t = |beta|
/// (e.g. Barfoot, "State Estimation for Robotics", 2017; equal to the form of Gallego
/// & Yezzi, "A compact formula for the derivative of a 3-D rotation in exponential coordinates",
/// JMIV 2015), evaluated with Taylor series of its coefficients for small t, so that it is exact
/// (to rounding) everywhere including beta = 0.
///
/// Conventions: pi as in types.hpp; SI units; angles in radians.
#pragma once

#include <array>

#include "inertial/inertia/parameterization.hpp"

namespace inertial {

/// Indices into phi (Section III-A). Use these names, never bare numbers.
namespace phi_index {
inline constexpr int kMass = 0;
inline constexpr int kCx = 1;
inline constexpr int kCy = 2;
inline constexpr int kCz = 3;
inline constexpr int kBeta1 = 4;
inline constexpr int kBeta2 = 5;
inline constexpr int kBeta3 = 6;
inline constexpr int kLx = 7;
inline constexpr int kLy = 8;
inline constexpr int kLz = 9;
}  // namespace phi_index

/// R = exp(S(beta)) (Rodrigues). If dR_dbeta is not null, also (*dR_dbeta)[k] = dR/dbeta_k
/// = S(J_l(beta) e_k) R (see the file comment), exact at every beta including 0.
Matrix3 RotationFromExponentialCoordinates(const Vector3& beta, std::array<Matrix3, 3>* dR_dbeta = nullptr);

/// beta = log(R) with |beta| <= pi, for a rotation matrix R (orthonormal, det +1; no check). Uses
/// the antisymmetric part of R for angles below pi/2 and the symmetric part above, so that it is
/// accurate up to and at the angle pi (where either of the two preimages +-pi a is returned).
Vector3 ExponentialCoordinatesOfRotation(const Matrix3& R);

/// The closed form of det(J_pi_phi) (see the file comment); zero iff m = 0, two L are equal, or
/// |beta| is a nonzero multiple of 2 pi.
double EigenvalueJacobianDeterminant(const Vector10& phi);

/// x = phi (Section III-A). Not a vector-space parameterization of the consistent bodies: see the
/// file comment for its singularities and non-uniqueness.
class EigenvalueParameterization final : public Parameterization {
 public:
  std::string_view name() const override { return "eigenvalue"; }

  /// pi(phi) and, optionally, the analytic J_pi_phi. Any phi (also m <= 0 or L <= 0) gives a
  /// finite pi.
  Vector10 ToPi(const Vector10& phi, Matrix10* J_pi_phi = nullptr) const override;

  /// One preimage of pi: m = pi's mass, c = h / m, R the eigenvectors of Sigma_Bcm_B
  /// (= tr(I_Bcm_B)/2 1 - I_Bcm_B) made a rotation (det +1), beta = log(R) with |beta| <= pi and
  /// L the eigenvalues in ascending order, matching R's columns. Returns false (*phi untouched) if
  /// pi is not finite, m <= 0, or some L is not positive; a body whose smallest L is below 1e-12
  /// times its scale max(|L|) + m |c|^2 (a point, rod or plate up to rounding) counts as not
  /// positive.
  bool FromPi(const Vector10& pi, Vector10* phi) const override;

  /// phi gives a fully consistent body iff it is finite with m > 0 and every L > 0 (Theorem II.1
  /// with eq. 5; ToPi itself does not constrain them), and pi(phi) does not overflow.
  bool YieldsConsistentBody(const Vector10& phi) const override;
};

}  // namespace inertial
