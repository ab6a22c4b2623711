#include "inertial/inertia/inertial_params.hpp"

#include <sstream>

#include "inertial/inertia/assert.hpp"
#include <stdexcept>

namespace inertial {
namespace {

Vector10 PackPi(double m, const Vector3& h, const Matrix3& I) {
  Vector10 pi;
  pi[pi_index::kMass] = m;
  pi.segment<3>(pi_index::kHx) = h;
  pi[pi_index::kIxx] = I(0, 0);
  pi[pi_index::kIyy] = I(1, 1);
  pi[pi_index::kIzz] = I(2, 2);
  pi[pi_index::kIxy] = 0.5 * (I(0, 1) + I(1, 0));
  pi[pi_index::kIyz] = 0.5 * (I(1, 2) + I(2, 1));
  pi[pi_index::kIxz] = 0.5 * (I(0, 2) + I(2, 0));
  return pi;
}

Matrix3 InertiaFromPi(const Vector10& pi) {
  Matrix3 I;
  I << pi[pi_index::kIxx], pi[pi_index::kIxy], pi[pi_index::kIxz],  //
      pi[pi_index::kIxy], pi[pi_index::kIyy], pi[pi_index::kIyz],   //
      pi[pi_index::kIxz], pi[pi_index::kIyz], pi[pi_index::kIzz];
  return I;
}

}  // namespace

InertialParams InertialParams::FromMassFirstMomentInertia(double m, const Vector3& h_B, const Matrix3& I_Bo_B) {
  return InertialParams(PackPi(m, h_B, I_Bo_B));
}

InertialParams InertialParams::FromMassComInertia(double m, const Vector3& p_BoBcm_B, const Matrix3& I_Bcm_B) {
  const Matrix3 shift = m * (p_BoBcm_B.squaredNorm() * Matrix3::Identity() - p_BoBcm_B * p_BoBcm_B.transpose());
  return InertialParams(PackPi(m, m * p_BoBcm_B, I_Bcm_B + shift));
}

InertialParams InertialParams::FromSpatialInertia(const Matrix6& M, double tolerance) {
  const double m = M(3, 3);
  const Matrix3 S_h = M.block<3, 3>(0, 3);
  const Vector3 h(S_h(2, 1), S_h(0, 2), S_h(1, 0));
  auto fail = [&](const char* what, double deviation) {
    std::ostringstream os;
    os << "spatial inertia is not of the form [[I, S(h)], [S(h)^T, m 1]]: " << what << " (deviation "
       << deviation << " > tolerance " << tolerance << ")";
    throw std::invalid_argument(os.str());
  };
  if (!M.allFinite()) throw std::invalid_argument("spatial inertia has a non-finite entry");
  const double asym = (M - M.transpose()).cwiseAbs().maxCoeff();
  if (asym > tolerance) fail("not symmetric", asym);
  const double mass_block = (M.block<3, 3>(3, 3) - m * Matrix3::Identity()).cwiseAbs().maxCoeff();
  if (mass_block > tolerance) fail("lower-right block is not m times identity", mass_block);
  const double skew = (S_h - Skew(h)).cwiseAbs().maxCoeff();
  if (skew > tolerance) fail("upper-right block is not skew-symmetric", skew);
  return InertialParams(PackPi(m, h, M.block<3, 3>(0, 0)));
}

InertialParams InertialParams::FromPseudoInertia(const Matrix4& J, double tolerance) {
  if (!J.allFinite()) throw std::invalid_argument("pseudo-inertia has a non-finite entry");
  const double asym = (J - J.transpose()).cwiseAbs().maxCoeff();
  if (asym > tolerance) {
    std::ostringstream os;
    os << "pseudo-inertia is not symmetric (largest |J - J^T| entry " << asym << " > tolerance " << tolerance << ")";
    throw std::invalid_argument(os.str());
  }
  return InertialParams(PiFromPseudoInertia(J));
}

Matrix3 InertialParams::rotational_inertia_about_origin() const { return InertiaFromPi(pi_); }

Matrix3 InertialParams::rotational_inertia_about_com() const {
  INERTIAL_ASSERT(mass() != 0.0);
  const Vector3 c = com();
  return InertiaFromPi(pi_) - mass() * (c.squaredNorm() * Matrix3::Identity() - c * c.transpose());
}

Matrix6 InertialParams::spatial_inertia() const {
  Matrix6 M;
  const Matrix3 S_h = Skew(first_moment());
  M.block<3, 3>(0, 0) = rotational_inertia_about_origin();
  M.block<3, 3>(0, 3) = S_h;
  M.block<3, 3>(3, 0) = S_h.transpose();
  M.block<3, 3>(3, 3) = mass() * Matrix3::Identity();
  return M;
}

Matrix3 InertialParams::second_moments_about_origin() const {
  const Matrix3 I = rotational_inertia_about_origin();
  return 0.5 * I.trace() * Matrix3::Identity() - I;
}

Matrix4 InertialParams::pseudo_inertia() const { return PseudoInertiaFromPi(pi_); }

InertialParams InertialParams::Transformed(const Matrix3& R_AB, const Vector3& p_AoBo_A) const {
  Matrix4 T = Matrix4::Identity();
  T.block<3, 3>(0, 0) = R_AB;
  T.block<3, 1>(0, 3) = p_AoBo_A;
  return InertialParams(PiFromPseudoInertia(T * pseudo_inertia() * T.transpose()));
}

Matrix4 PseudoInertiaGradient(const Vector10& g) {
  Matrix4 G;
  G(3, 3) = g[pi_index::kMass];
  for (int k = 0; k < 3; ++k) G(k, 3) = G(3, k) = 0.5 * g[pi_index::kHx + k];
  G(0, 0) = g[pi_index::kIyy] + g[pi_index::kIzz];
  G(1, 1) = g[pi_index::kIxx] + g[pi_index::kIzz];
  G(2, 2) = g[pi_index::kIxx] + g[pi_index::kIyy];
  G(0, 1) = G(1, 0) = -0.5 * g[pi_index::kIxy];
  G(1, 2) = G(2, 1) = -0.5 * g[pi_index::kIyz];
  G(0, 2) = G(2, 0) = -0.5 * g[pi_index::kIxz];
  return G;
}

Matrix4 PseudoInertiaFromPi(const Vector10& pi) {
  const Matrix3 I = InertiaFromPi(pi);
  Matrix4 J;
  J.block<3, 3>(0, 0) = 0.5 * I.trace() * Matrix3::Identity() - I;
  J.block<3, 1>(0, 3) = pi.segment<3>(pi_index::kHx);
  J.block<1, 3>(3, 0) = pi.segment<3>(pi_index::kHx).transpose();
  J(3, 3) = pi[pi_index::kMass];
  return J;
}

Vector10 PiFromPseudoInertia(const Matrix4& J) {
  const Matrix3 Sigma = 0.5 * (J.block<3, 3>(0, 0) + J.block<3, 3>(0, 0).transpose());
  const Matrix3 I = Sigma.trace() * Matrix3::Identity() - Sigma;
  const Vector3 h = 0.5 * (J.block<3, 1>(0, 3) + J.block<1, 3>(3, 0).transpose());
  return PackPi(J(3, 3), h, I);
}

}  // namespace inertial
