#include "inertial/inertia/exponential_parameterization.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

#include "inertial/inertia/inertial_params.hpp"

namespace inertial {

namespace {

/// FromPi refuses pseudo-inertias whose smallest eigenvalue is not above this fraction of the
/// largest (rounding noise in the eigenvalues is a few machine epsilons times the largest).
constexpr double kDegenerateRelativeTolerance = 1e-12;

/// The divided difference (e^a - e^b) / (a - b), and its limit e^a at a = b, without cancellation:
/// with M = max(a, b) and d = -|a - b| <= 0 it equals e^M expm1(d) / d (expm1 is accurate for small
/// |d| and lies in (-1, 0], so nothing overflows that e^M does not).
double ExpDividedDifference(double a, double b) {
  const double M = std::max(a, b);
  const double d = -std::abs(a - b);
  if (d == 0.0) return std::exp(M);
  return std::exp(M) * (std::expm1(d) / d);
}

Matrix4 SymmetricPart(const Matrix4& A) { return 0.5 * (A + A.transpose()); }

/// log(K) if the symmetric part of K is finite with smallest eigenvalue > 0 and
/// > relative_floor * largest eigenvalue; false (*Q untouched) otherwise.
bool LogOfPositiveDefinite(const Matrix4& K, double relative_floor, Matrix4* Q) {
  if (!K.allFinite()) return false;
  const Eigen::SelfAdjointEigenSolver<Matrix4> eig(SymmetricPart(K));
  if (eig.info() != Eigen::Success) return false;
  const Vector4& l = eig.eigenvalues();  // ascending
  if (!(l[0] > 0.0 && l[0] > relative_floor * l[3])) return false;
  const Matrix4& V = eig.eigenvectors();
  const Matrix4 result = V * l.array().log().matrix().asDiagonal() * V.transpose();
  if (!result.allFinite()) return false;
  *Q = result;
  return true;
}

}  // namespace

Matrix4 SymmetricFromExponentialParameters(const Vector10& x) {
  Matrix4 Q;
  for (int k = 0; k < 10; ++k) {
    Q(kExponentialSlots[k].row, kExponentialSlots[k].col) = x[k];
    Q(kExponentialSlots[k].col, kExponentialSlots[k].row) = x[k];
  }
  return Q;
}

Vector10 ExponentialParametersFromSymmetric(const Matrix4& Q) {
  const Matrix4 S = SymmetricPart(Q);
  Vector10 x;
  for (int k = 0; k < 10; ++k) x[k] = S(kExponentialSlots[k].row, kExponentialSlots[k].col);
  return x;
}

Matrix4 SymmetricMatrixExp(const Matrix4& Q) {
  const Eigen::SelfAdjointEigenSolver<Matrix4> eig(SymmetricPart(Q));
  const Matrix4& V = eig.eigenvectors();
  return V * eig.eigenvalues().array().exp().matrix().asDiagonal() * V.transpose();
}

bool SymmetricMatrixLog(const Matrix4& K, Matrix4* Q) { return LogOfPositiveDefinite(K, 0.0, Q); }

double ExponentialJacobianDeterminant(const Vector10& x) {
  const Eigen::SelfAdjointEigenSolver<Matrix4> eig(SymmetricFromExponentialParameters(x), Eigen::EigenvaluesOnly);
  const Vector4& l = eig.eigenvalues();
  // The sign and factor of the linear map J -> pi (see the header).
  constexpr double kPiFromJDeterminant = -2.0;
  double det = kPiFromJDeterminant;
  for (int i = 0; i < 4; ++i) {
    for (int j = i; j < 4; ++j) det *= ExpDividedDifference(l[i], l[j]);
  }
  return det;
}

Vector10 ExponentialParameterization::ToPi(const Vector10& x, Matrix10* J_pi_x) const {
  const Eigen::SelfAdjointEigenSolver<Matrix4> eig(SymmetricFromExponentialParameters(x));
  const Matrix4& V = eig.eigenvectors();
  const Vector4& l = eig.eigenvalues();
  const Matrix4 K = V * l.array().exp().matrix().asDiagonal() * V.transpose();
  const Vector10 pi = PiFromPseudoInertia(K);

  if (J_pi_x != nullptr) {
    Matrix4 G;
    for (int i = 0; i < 4; ++i) {
      for (int j = 0; j < 4; ++j) G(i, j) = ExpDividedDifference(l[i], l[j]);
    }
    for (int k = 0; k < 10; ++k) {
      const int r = kExponentialSlots[k].row, c = kExponentialSlots[k].col;
      // V^T E V for E = e_r e_c^T + e_c e_r^T (or e_r e_r^T on the diagonal).
      Matrix4 M = V.row(r).transpose() * V.row(c);
      if (r != c) M += M.transpose().eval();
      const Matrix4 dK = V * G.cwiseProduct(M) * V.transpose();
      J_pi_x->col(k) = PiFromPseudoInertia(dK);
    }
  }
  return pi;
}

bool ExponentialParameterization::FromPi(const Vector10& pi, Vector10* x) const {
  if (!pi.allFinite()) return false;
  Matrix4 Q;
  if (!LogOfPositiveDefinite(PseudoInertiaFromPi(pi), kDegenerateRelativeTolerance, &Q)) return false;
  const Vector10 result = ExponentialParametersFromSymmetric(Q);
  if (!result.allFinite()) return false;
  *x = result;
  return true;
}

bool ExponentialParameterization::YieldsConsistentBody(const Vector10& x) const {
  return x.allFinite() && ToPi(x).allFinite();
}

}  // namespace inertial
