/// @file log_cholesky.hpp
/// The log-Cholesky parameterization of rigid-body inertia (Rucker & Wensing 2022, Section IV-B).
///
/// theta = [alpha, d1, d2, d3, s12, s23, s13, t1, t2, t3] builds the upper-triangular
///
///   U = e^alpha [[e^d1, s12, s13, t1],
///                [0,    e^d2, s23, t2],
///                [0,    0,    e^d3, t3],
///                [0,    0,    0,    1 ]]                                   (eq. 8)
///
/// and the pseudo-inertia J = U J0 U^T (eq. 11; eq. 7 is J0 = 1), from which pi follows linearly.
/// Every theta in R^10 gives a fully physically consistent body and every such body has exactly one
/// theta: a diffeomorphism R^10 -> C. Physical meaning (Section V-B): t translates the reference
/// body (so h = m t for J0 = 1), d_i stretch it along the axes, s_ij shear it, and e^{2 alpha}
/// scales its density (m = e^{2 alpha} for J0 = 1).
///
/// Closed form for J0 = 1, with E = e^{2 alpha}, e_i = e^{d_i} (this is pi(U U^T); the paper's
/// printed eq. 9 expands U^T U instead):
///   m   = E
///   h   = E [t1, t2, t3]
///   Sigma = E (U3 U3^T + t t^T), U3 the upper-left 3x3 of U / e^alpha, i.e.
///     S00 = e1^2 + s12^2 + s13^2 + t1^2,  S11 = e2^2 + s23^2 + t2^2,  S22 = e3^2 + t3^2,
///     S01 = s12 e2 + s13 s23 + t1 t2,     S12 = s23 e3 + t2 t3,       S02 = s13 e3 + t1 t3
///   Ixx = E (S11 + S22), Iyy = E (S00 + S22), Izz = E (S00 + S11),
///   Ixy = -E S01,        Iyz = -E S12,        Ixz = -E S02.
/// det(J_pi_theta) = -32 e^{20 alpha + 2 d1 + 3 d2 + 4 d3} (derived in the README's math notes;
/// never zero, so the map is a local diffeomorphism everywhere).
///
/// Conventions: pi and theta orders as in types.hpp; SI units; t in metres.
#pragma once

#include <string>

#include "inertial/inertia/inertial_params.hpp"
#include "inertial/inertia/parameterization.hpp"

namespace inertial {

/// U(theta) of eq. (8).
Matrix4 LogCholeskyFactor(const Vector10& theta);

/// pi(theta) for the identity reference (J = U U^T), closed form; J_pi_theta (optional) analytic.
Vector10 PiFromLogCholesky(const Vector10& theta, Matrix10* J_pi_theta = nullptr);

/// The closed form of det(J_pi_theta) for the identity reference (see the file comment).
double LogCholeskyJacobianDeterminant(const Vector10& theta);

/// Upper-triangular U with positive diagonal and J = U U^T (eq. 7), if J is symmetric positive
/// definite (returns false otherwise, *U untouched).
bool UpperCholesky(const Matrix4& J, Matrix4* U);

/// The log-Cholesky map relative to a reference body J0 (eq. 11): theta = 0 is the reference.
class LogCholeskyParameterization final : public Parameterization {
 public:
  /// Reference J0 = 1 (the 4x4 identity; a body of 1 kg at the origin with second moments
  /// 1 kg m^2 about each axis, i.e. rotational inertia 2 kg m^2 about each axis): eq. (7)-(9).
  LogCholeskyParameterization();
  /// Reference = a prior body (e.g. from CAD).
  /// @throws std::invalid_argument naming the failed condition if `reference` is not fully
  /// physically consistent (a degenerate reference would make the map non-invertible).
  explicit LogCholeskyParameterization(const InertialParams& reference);

  std::string_view name() const override { return "log_cholesky"; }
  Vector10 ToPi(const Vector10& theta, Matrix10* J_pi_theta = nullptr) const override;
  /// pi(theta) and A d(pi)/d(theta) for one body's 6 x 10 regressor A, without forming the
  /// Jacobian: its alpha column is 2 pi, and each other column has at most five distinct nonzeros
  /// (a perturbation of one row of U: one entry of h, two equal diagonal entries of I, two
  /// off-diagonal ones), so A J costs 49 column operations instead of 100. Never allocates.
  Vector10 ToPiProjected(const Vector10& theta, const Matrix6x10& A, Matrix6x10* AJ) const;
  bool FromPi(const Vector10& pi, Vector10* theta) const override;
  /// Every finite theta gives a fully consistent body (Section IV-B), unless pi overflows
  /// (e^{2 alpha} beyond the range of a double).
  bool YieldsConsistentBody(const Vector10& theta) const override { return theta.allFinite() && ToPi(theta).allFinite(); }

  /// The Hessian of the scalar g . pi(theta) with respect to theta (10x10, symmetric), exact: for
  /// pi linear in J = U J0 U^T, g . pi = tr(G J) with G symmetric, so
  ///   d2/dtheta_k dtheta_l = 2 tr(G U_kl J0 U^T) + 2 tr(G U_k J0 U_l^T) (symmetrized),
  /// where U_k, U_kl are the first and second derivatives of U (eq. 8); U_kl is non-zero only for
  /// (alpha, any) and (d_i, d_i). Used for Newton steps of least-squares fits (the second-order
  /// term sum_k g_k d2 pi_k / dtheta2 that Gauss-Newton drops).
  Matrix10 ContractedHessian(const Vector10& theta, const Vector10& g) const;
  /// The inverse at a boundary: theta of a body.
  /// @throws std::invalid_argument with the consistency report's reason if `body` is not fully
  /// physically consistent.
  Vector10 ThetaOf(const InertialParams& body) const;

  /// The reference pseudo-inertia J0.
  const Matrix4& reference_pseudo_inertia() const { return J0_; }
  bool has_identity_reference() const { return identity_reference_; }

 private:
  Matrix4 J0_ = Matrix4::Identity();
  Matrix4 U0_ = Matrix4::Identity();  // upper Cholesky factor of J0
  bool identity_reference_ = true;
};

}  // namespace inertial
