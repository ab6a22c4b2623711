/// @file exponential_parameterization.hpp
/// The exponential-map parameterization of rigid-body inertia (Rucker & Wensing 2022, Section IV-A):
/// the pseudo-inertia is the matrix exponential of a symmetric 4x4 matrix,
///
///   J = K = exp(Q) = sum_k Q^k / k!,   Q in S^4,   pi = pi(J) (linear; Section IV).
///
/// x holds the 10 unique entries of Q in the slots in which pi holds the entries of J (row/column
/// 3 is the mass row; rows/columns 0..2 the x, y, z second moments):
///
///   x = [Q33, Q03, Q13, Q23, Q00, Q11, Q22, Q01, Q12, Q02]    (0-based indices)
///
/// Every x in R^10 gives a positive definite J, i.e. a fully physically consistent body, and every
/// such body has exactly one x (Q = log(J)): a bijection R^10 -> C. x = 0 is J = 1, the same unit
/// reference body as the log-Cholesky map's theta = 0 (1 kg at the origin, second moments
/// 1 kg m^2 along each axis). Unlike the log-Cholesky map this one is not in closed form.
///
/// Computation: with the symmetric eigen-decomposition Q = V diag(l) V^T,
///   exp(Q) = V diag(e^l) V^T,   log(K) = V diag(log l) V^T (K positive definite),
/// and the exact Jacobian from the Daleckii-Krein formula for the Frechet derivative of a function
/// of a symmetric matrix (Daleckii & Krein 1965; Higham, "Functions of Matrices", 2008, Thm. 3.11):
///   d exp(Q)[E] = V (G o (V^T E V)) V^T,   G_ij = (e^li - e^lj) / (li - lj)  (e^li if li = lj),
/// with o the entrywise product and E the symmetric unit matrix of one slot of x (1 at (i, j) and
/// (j, i) for an off-diagonal slot). G_ij is evaluated as e^max(li,lj) expm1(-|li - lj|) / (-|li - lj|),
/// which has no cancellation for nearly equal eigenvalues and no overflow beyond that of e^max(l);
/// it is continuous in l, so repeated eigenvalues (e.g. Q = 0) need no special treatment.
///
/// det(J_pi_x) = -2 prod_{i <= j} G_ij: the Frechet derivative is diagonal in the basis
/// V (e_i e_j^T + e_j e_i^T) V^T of S^4 with eigenvalues G_ij (x and the entries of J share the
/// slot order, so that part needs no change of basis), and pi is linear in J with determinant -2
/// (Ixx = S11 + S22 etc. contributes 2, the three signs Ixy = -S01 etc. contribute -1). Every G_ij
/// is positive, so the map is a local diffeomorphism everywhere (no singularities).
///
/// Conventions: pi as in types.hpp; SI units (the entries of Q are logarithms of a matrix that mixes
/// kg m^2, kg m and kg, so they are unitless only relative to the unit body above).
#pragma once

#include "inertial/inertia/parameterization.hpp"

namespace inertial {

/// Indices into x: the entry of Q held by each slot (0-based row and column, 3 = mass row).
namespace exponential_index {
inline constexpr int kQ33 = 0;
inline constexpr int kQ03 = 1;
inline constexpr int kQ13 = 2;
inline constexpr int kQ23 = 3;
inline constexpr int kQ00 = 4;
inline constexpr int kQ11 = 5;
inline constexpr int kQ22 = 6;
inline constexpr int kQ01 = 7;
inline constexpr int kQ12 = 8;
inline constexpr int kQ02 = 9;
}  // namespace exponential_index

/// Row and column of Q for a slot of x.
struct SymmetricEntry {
  int row;
  int col;
};

/// The (row, col) of Q held in slot k of x, for k = 0..9 (see exponential_index).
inline constexpr SymmetricEntry kExponentialSlots[10] = {{3, 3}, {0, 3}, {1, 3}, {2, 3}, {0, 0},
                                                         {1, 1}, {2, 2}, {0, 1}, {1, 2}, {0, 2}};

/// The symmetric Q with the entries of x (slot order above).
Matrix4 SymmetricFromExponentialParameters(const Vector10& x);

/// The entries of the symmetric part of Q in slot order.
Vector10 ExponentialParametersFromSymmetric(const Matrix4& Q);

/// exp(Q) for symmetric Q (only the symmetric part is used), via the eigen-decomposition.
Matrix4 SymmetricMatrixExp(const Matrix4& Q);

/// log(K) for symmetric positive definite K: returns false (*Q untouched) if K is not finite or has
/// an eigenvalue <= 0 (only the symmetric part of K is used).
bool SymmetricMatrixLog(const Matrix4& K, Matrix4* Q);

/// The closed form of det(J_pi_x) above (never zero).
double ExponentialJacobianDeterminant(const Vector10& x);

class ExponentialParameterization final : public Parameterization {
 public:
  std::string_view name() const override { return "exponential"; }

  /// pi(exp(Q(x))) and, optionally, the exact J_pi_x (Daleckii-Krein, see the file comment).
  Vector10 ToPi(const Vector10& x, Matrix10* J_pi_x = nullptr) const override;

  /// x = Q(log(J(pi))). Returns false (*x untouched) if pi is not finite or J(pi) is not positive
  /// definite; a J whose smallest eigenvalue is below 1e-12 times its largest (a point, rod or
  /// plate up to rounding) counts as not positive definite.
  bool FromPi(const Vector10& pi, Vector10* x) const override;

  /// Every finite x gives a fully consistent body (exp(Q) is positive definite), even where its
  /// numerical margins round to zero; false only if x is not finite or exp(Q) overflows (an
  /// eigenvalue of Q above ~709).
  bool YieldsConsistentBody(const Vector10& x) const override;
};

}  // namespace inertial
