/// @file bounding_ellipsoid.hpp
/// The region a body's mass may occupy, as an ellipsoid, and the condition on its inertial
/// parameters that follows (Wensing, Kim and Slotine, "Linear matrix inequalities for physically
/// consistent inertial parameter identification: a statistical perspective on the mass
/// distribution", IEEE RA-L 2018, Section IV).
///
/// The ellipsoid E = {x : (x - c)^T P (x - c) <= 1} (P = S^-1 symmetric positive definite, S the
/// matrix whose eigenvalues are the squared semi-axes) is E = {x : [x; 1]^T Q [x; 1] >= 0} with
///   Q = [ -P      P c         ]
///       [ c^T P   1 - c^T P c ].
/// A body all of whose mass lies in E has tr(Q J) = integral of [x;1]^T Q [x;1] rho(x) dV >= 0 for its
/// pseudo-inertia J (eq. 5 of the log-Cholesky paper: J = integral [x;1][x;1]^T rho dV), because
/// the integrand is non-negative on E. (Necessary, not sufficient: the condition says that the mass's
/// mean normalized squared distance from c is at most 1, the RA-L paper's "the second moment fits").
/// tr(Q J) is linear in pi: tr(Q J) = q . pi (RegionCoefficients). Its value divided by the mass,
///   s = tr(Q J) / m = 1 - E_rho[(x - c)^T P (x - c)]  in (-inf, 1],
/// is the body's slack in its region: 1 for all mass at the centre, 0 on the condition's boundary,
/// negative outside. It is scale-free (a body and the same body 10 times heavier have the same s).
///
/// The smallest ellipsoid holding a set of points (MinimumVolumeEllipsoid) is Khachiyan's
/// algorithm (L. G. Khachiyan, "Rounding of polytopes in the real number model of computation",
/// Math. Oper. Res. 21(2), 1996; as written out by Todd and Yildirim, 2007): weights u on the
/// points, X(u) = sum_i u_i [p_i;1][p_i;1]^T, repeatedly moving weight to the point of largest
/// [p;1]^T X^-1 [p;1] until that exceeds d + 1 = 4 by at most the tolerance; then c = sum u_i p_i
/// and P = (sum u_i (p_i - c)(p_i - c)^T)^-1 / 3, scaled so that every point lies inside.
///
/// Conventions: SI units (m); c and P in the frame the points (and the body's pi) are given in.
#pragma once

#include <vector>

#include "inertial/inertia/inertial_params.hpp"

namespace inertial {

struct BoundingEllipsoid {
  Vector3 center = Vector3::Zero();
  Matrix3 shape_inverse = Matrix3::Identity();  ///< P: (x - c)^T P (x - c) <= 1 inside [1/m^2]

  /// An ellipsoid with semi-axes `semi_axes` along the columns of `axes` (orthonormal) about `center`.
  /// @throws std::invalid_argument if a semi-axis is not positive and finite.
  static BoundingEllipsoid FromAxes(const Vector3& center, const Matrix3& axes, const Vector3& semi_axes);

  /// The semi-axes, ascending [m].
  Vector3 SemiAxes() const;
  /// Volume 4/3 pi a b c [m^3].
  double Volume() const;
  /// Whether (x - c)^T P (x - c) <= 1 (with a relative tolerance of 1e-12).
  bool Contains(const Vector3& x) const;
  /// The same ellipsoid with every semi-axis multiplied by `factor` (> 0).
  BoundingEllipsoid Scaled(double factor) const;
  /// The 4 x 4 matrix Q of the file comment.
  Matrix4 Q() const;
  /// q with tr(Q J(pi)) = q . pi for every pi (types.hpp order).
  Vector10 RegionCoefficients() const;
  /// The slack s = tr(Q J) / m of a body (file comment); -infinity for a mass that is not positive.
  double Slack(const InertialParams& body) const;
};

/// The smallest-volume ellipsoid holding every point (file comment), to within a factor of about
/// 1 + tolerance in volume, and then grown so that it holds each point exactly.
/// @throws std::invalid_argument if there are fewer than 4 points, a point is not finite, or the
/// points lie in a plane (no ellipsoid of positive volume is determined by them).
BoundingEllipsoid MinimumVolumeEllipsoid(const std::vector<Vector3>& points, double tolerance = 1e-4);

/// The solid ellipsoid of uniform density with the same mass, COM and second moments as `body`:
/// its semi-axes are sqrt(5 lambda_i) along the eigenvectors of Sigma_c / m (lambda_i its
/// eigenvalues, Sigma_c the second moment about the COM). Every fully consistent body has one.
/// @throws std::invalid_argument if the body's mass is not positive or Sigma_c is not positive definite.
BoundingEllipsoid EquivalentUniformEllipsoid(const InertialParams& body);

}  // namespace inertial
