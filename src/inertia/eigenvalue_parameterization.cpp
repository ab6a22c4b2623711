#include "inertial/inertia/eigenvalue_parameterization.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

#include "inertial/inertia/inertial_params.hpp"

namespace inertial {

using namespace phi_index;  // NOLINT: index names of phi

namespace {

/// Below this rotation angle [rad] the coefficient functions of exp(S(beta)) and J_l(beta) use their
/// Taylor series (truncated after t^4: the first omitted term is below 3e-22 there), above it the
/// closed forms (whose cancellation error is then below 1e-15 absolute in R and dR).
constexpr double kSmallAngle = 1e-3;

/// FromPi refuses bodies whose smallest second moment is not above this fraction of the scale of
/// the computation (rounding noise in L is a few machine epsilons times that scale).
constexpr double kDegenerateRelativeTolerance = 1e-12;

/// The coefficient functions of Rodrigues' formula and of the left Jacobian of SO(3) at angle t:
///   exp(S(beta)) = 1 + a S(beta) + b S(beta)^2,   J_l(beta) = 1 + b S(beta) + c S(beta)^2.
struct RotationCoefficients {
  double a;  ///< sin t / t
  double b;  ///< (1 - cos t) / t^2
  double c;  ///< (t - sin t) / t^3
};

RotationCoefficients CoefficientsAtAngle(double t) {
  RotationCoefficients k;
  const double t2 = t * t;
  if (t < kSmallAngle) {
    const double t4 = t2 * t2;
    k.a = 1.0 - t2 / 6.0 + t4 / 120.0;
    k.b = 0.5 - t2 / 24.0 + t4 / 720.0;
    k.c = 1.0 / 6.0 - t2 / 120.0 + t4 / 5040.0;
  } else {
    const double s = std::sin(t);
    const double half_sin = std::sin(0.5 * t);
    k.a = s / t;
    k.b = 2.0 * half_sin * half_sin / t2;  // 1 - cos t = 2 sin^2(t/2), without cancellation
    k.c = (t - s) / (t2 * t);
  }
  return k;
}

/// The diagonal of D = diag(Ly + Lz, Lx + Lz, Lx + Ly) (eq. 5).
Vector3 PrincipalMoments(const Vector3& L) { return Vector3(L.y() + L.z(), L.x() + L.z(), L.x() + L.y()); }

/// pi from mass, first moment and a rotational inertia about Bo (used for pi and its derivatives,
/// which are pi of the derivatives since the packing is linear).
Vector10 Pack(double m, const Vector3& h, const Matrix3& I_Bo_B) {
  return InertialParams::FromMassFirstMomentInertia(m, h, I_Bo_B).vector();
}

}  // namespace

Matrix3 RotationFromExponentialCoordinates(const Vector3& beta, std::array<Matrix3, 3>* dR_dbeta) {
  const RotationCoefficients k = CoefficientsAtAngle(beta.norm());
  const Matrix3 S = Skew(beta);
  const Matrix3 S2 = S * S;
  const Matrix3 R = Matrix3::Identity() + k.a * S + k.b * S2;
  if (dR_dbeta != nullptr) {
    const Matrix3 J_l = Matrix3::Identity() + k.b * S + k.c * S2;
    for (int i = 0; i < 3; ++i) (*dR_dbeta)[i] = Skew(J_l.col(i)) * R;
  }
  return R;
}

Vector3 ExponentialCoordinatesOfRotation(const Matrix3& R) {
  // R = cos t 1 + sin t S(a) + (1 - cos t) a a^T for the unit axis a and angle t in [0, pi].
  const Vector3 v = 0.5 * Vector3(R(2, 1) - R(1, 2), R(0, 2) - R(2, 0), R(1, 0) - R(0, 1));  // sin t a
  const double sin_t = v.norm();
  const double cos_t = 0.5 * (R.trace() - 1.0);
  const double t = std::atan2(sin_t, cos_t);
  if (cos_t > 0.0) {
    // t < pi/2: t / sin t is in [1, pi/2) and the antisymmetric part determines beta accurately.
    if (sin_t == 0.0) return Vector3::Zero();
    return (t / sin_t) * v;
  }
  // t >= pi/2: a a^T = ((R + R^T)/2 - cos t 1) / (1 - cos t), with 1 - cos t in [1, 2]. The column
  // with the largest diagonal entry (a_j^2 >= 1/3) gives a up to sign, fixed by sin t a.
  const Matrix3 aaT = (0.5 * (R + R.transpose()) - cos_t * Matrix3::Identity()) / (1.0 - cos_t);
  int j = 0;
  aaT.diagonal().maxCoeff(&j);
  Vector3 a = aaT.col(j).normalized();
  if (a.dot(v) < 0.0) a = -a;
  return t * a;
}

double EigenvalueJacobianDeterminant(const Vector10& phi) {
  // The factors of the header's derivation: the linear map J -> pi, (c -> h = m c), det J_l(beta)
  // = 2 (1 - cos t) / t^2, and the second-moment differences.
  constexpr double kPiFromJDeterminant = -2.0;
  const double m = phi[kMass];
  const double det_J_l = 2.0 * CoefficientsAtAngle(phi.segment<3>(kBeta1).norm()).b;
  const double Lx = phi[kLx], Ly = phi[kLy], Lz = phi[kLz];
  return kPiFromJDeterminant * m * m * m * det_J_l * (Lx - Ly) * (Ly - Lz) * (Lx - Lz);
}

Vector10 EigenvalueParameterization::ToPi(const Vector10& phi, Matrix10* J_pi_phi) const {
  const double m = phi[kMass];
  const Vector3 c = phi.segment<3>(kCx);
  const Vector3 beta = phi.segment<3>(kBeta1);
  const Vector3 L = phi.segment<3>(kLx);

  std::array<Matrix3, 3> dR;
  const Matrix3 R = RotationFromExponentialCoordinates(beta, J_pi_phi != nullptr ? &dR : nullptr);
  const Vector3 D = PrincipalMoments(L);
  const Matrix3 I_Bcm_B = R * D.asDiagonal() * R.transpose();
  // Parallel-axis term per unit mass: |c|^2 1 - c c^T.
  const Matrix3 shift = c.squaredNorm() * Matrix3::Identity() - c * c.transpose();
  const Vector10 pi = Pack(m, m * c, I_Bcm_B + m * shift);

  if (J_pi_phi != nullptr) {
    Matrix10& J = *J_pi_phi;
    J.col(kMass) = Pack(1.0, c, shift);
    const int c_index[3] = {kCx, kCy, kCz};
    const int beta_index[3] = {kBeta1, kBeta2, kBeta3};
    const int L_index[3] = {kLx, kLy, kLz};
    for (int k = 0; k < 3; ++k) {
      const Vector3 e = Vector3::Unit(k);
      // d(shift)/dc_k = 2 c_k 1 - e_k c^T - c e_k^T.
      const Matrix3 dshift = 2.0 * c[k] * Matrix3::Identity() - e * c.transpose() - c * e.transpose();
      J.col(c_index[k]) = Pack(0.0, m * e, m * dshift);
      // d(R D R^T) = dR D R^T + (dR D R^T)^T.
      const Matrix3 A = dR[k] * D.asDiagonal() * R.transpose();
      J.col(beta_index[k]) = Pack(0.0, Vector3::Zero(), A + A.transpose());
      // dD/dL_k = 1 - e_k e_k^T (eq. 5: L_k enters the two principal moments other than D_k).
      const Vector3 dD = Vector3::Ones() - e;
      J.col(L_index[k]) = Pack(0.0, Vector3::Zero(), R * dD.asDiagonal() * R.transpose());
    }
  }
  return pi;
}

bool EigenvalueParameterization::FromPi(const Vector10& pi, Vector10* phi) const {
  if (!pi.allFinite()) return false;
  const double m = pi[pi_index::kMass];
  if (!(m > 0.0)) return false;
  const InertialParams body = InertialParams::FromVector(pi);
  const Vector3 c = body.com();
  const Matrix3 I_Bcm_B = body.rotational_inertia_about_com();
  const Matrix3 Sigma_Bcm_B = 0.5 * I_Bcm_B.trace() * Matrix3::Identity() - I_Bcm_B;

  const Eigen::SelfAdjointEigenSolver<Matrix3> eig(Sigma_Bcm_B);
  if (eig.info() != Eigen::Success) return false;
  const Vector3 L = eig.eigenvalues();  // ascending
  const double scale = L.cwiseAbs().maxCoeff() + m * c.squaredNorm();
  if (!(L.minCoeff() > kDegenerateRelativeTolerance * scale)) return false;

  Matrix3 R = eig.eigenvectors();
  if (R.determinant() < 0.0) R.col(2) = -R.col(2);  // a rotation, same principal axes

  Vector10 result;
  result[kMass] = m;
  result.segment<3>(kCx) = c;
  result.segment<3>(kBeta1) = ExponentialCoordinatesOfRotation(R);
  result.segment<3>(kLx) = L;
  if (!result.allFinite()) return false;
  *phi = result;
  return true;
}

bool EigenvalueParameterization::YieldsConsistentBody(const Vector10& phi) const {
  return phi.allFinite() && phi[kMass] > 0.0 && (phi.segment<3>(kLx).array() > 0.0).all() && ToPi(phi).allFinite();
}

}  // namespace inertial
