#include "inertial/inertia/log_cholesky.hpp"

#include <Eigen/Cholesky>
#include <cmath>
#include <stdexcept>

#include "inertial/inertia/consistency.hpp"

namespace inertial {

using namespace theta_index;  // NOLINT: index names of theta
namespace pi_ix = pi_index;

Matrix4 LogCholeskyFactor(const Vector10& theta) {
  const double s = std::exp(theta[kAlpha]);
  Matrix4 U;
  U << std::exp(theta[kD1]), theta[kS12], theta[kS13], theta[kT1],  //
      0.0, std::exp(theta[kD2]), theta[kS23], theta[kT2],           //
      0.0, 0.0, std::exp(theta[kD3]), theta[kT3],                   //
      0.0, 0.0, 0.0, 1.0;
  return s * U;
}

Vector10 PiFromLogCholesky(const Vector10& theta, Matrix10* J_pi_theta) {
  const double E = std::exp(2.0 * theta[kAlpha]);
  const double e1 = std::exp(theta[kD1]), e2 = std::exp(theta[kD2]), e3 = std::exp(theta[kD3]);
  const double s12 = theta[kS12], s23 = theta[kS23], s13 = theta[kS13];
  const double t1 = theta[kT1], t2 = theta[kT2], t3 = theta[kT3];

  // Second moments Sigma / E (see the header's closed form).
  const double S00 = e1 * e1 + s12 * s12 + s13 * s13 + t1 * t1;
  const double S11 = e2 * e2 + s23 * s23 + t2 * t2;
  const double S22 = e3 * e3 + t3 * t3;
  const double S01 = s12 * e2 + s13 * s23 + t1 * t2;
  const double S12 = s23 * e3 + t2 * t3;
  const double S02 = s13 * e3 + t1 * t3;

  Vector10 pi;
  pi[pi_ix::kMass] = E;
  pi[pi_ix::kHx] = E * t1;
  pi[pi_ix::kHy] = E * t2;
  pi[pi_ix::kHz] = E * t3;
  pi[pi_ix::kIxx] = E * (S11 + S22);
  pi[pi_ix::kIyy] = E * (S00 + S22);
  pi[pi_ix::kIzz] = E * (S00 + S11);
  pi[pi_ix::kIxy] = -E * S01;
  pi[pi_ix::kIyz] = -E * S12;
  pi[pi_ix::kIxz] = -E * S02;

  if (J_pi_theta != nullptr) {
    // d(Sigma/E)/d(theta) for theta without alpha; rows S00, S11, S22, S01, S12, S02.
    Eigen::Matrix<double, 6, 10> dS = Eigen::Matrix<double, 6, 10>::Zero();
    dS(0, kD1) = 2 * e1 * e1, dS(0, kS12) = 2 * s12, dS(0, kS13) = 2 * s13, dS(0, kT1) = 2 * t1;
    dS(1, kD2) = 2 * e2 * e2, dS(1, kS23) = 2 * s23, dS(1, kT2) = 2 * t2;
    dS(2, kD3) = 2 * e3 * e3, dS(2, kT3) = 2 * t3;
    dS(3, kD2) = s12 * e2, dS(3, kS12) = e2, dS(3, kS13) = s23, dS(3, kS23) = s13, dS(3, kT1) = t2, dS(3, kT2) = t1;
    dS(4, kD3) = s23 * e3, dS(4, kS23) = e3, dS(4, kT2) = t3, dS(4, kT3) = t2;
    dS(5, kD3) = s13 * e3, dS(5, kS13) = e3, dS(5, kT1) = t3, dS(5, kT3) = t1;

    Matrix10& J = *J_pi_theta;
    J.setZero();
    J(pi_ix::kHx, kT1) = E;
    J(pi_ix::kHy, kT2) = E;
    J(pi_ix::kHz, kT3) = E;
    J.row(pi_ix::kIxx) = E * (dS.row(1) + dS.row(2));
    J.row(pi_ix::kIyy) = E * (dS.row(0) + dS.row(2));
    J.row(pi_ix::kIzz) = E * (dS.row(0) + dS.row(1));
    J.row(pi_ix::kIxy) = -E * dS.row(3);
    J.row(pi_ix::kIyz) = -E * dS.row(4);
    J.row(pi_ix::kIxz) = -E * dS.row(5);
    J.col(kAlpha) = 2.0 * pi;  // every entry carries the factor e^{2 alpha}
  }
  return pi;
}

double LogCholeskyJacobianDeterminant(const Vector10& theta) {
  return -32.0 * std::exp(20.0 * theta[kAlpha] + 2.0 * theta[kD1] + 3.0 * theta[kD2] + 4.0 * theta[kD3]);
}

bool UpperCholesky(const Matrix4& J, Matrix4* U) {
  if (!J.allFinite()) return false;
  // With P the exchange (reversal) permutation, P J P = L L^T (lower Cholesky) gives
  // J = (P L P)(P L P)^T and P L P is upper triangular with the same positive diagonal.
  const Matrix4 Jr = J.reverse();  // reverses rows and columns: P J P
  const Eigen::LLT<Matrix4> llt(Jr);
  if (llt.info() != Eigen::Success) return false;
  const Matrix4 L = llt.matrixL();
  const Matrix4 result = L.reverse();
  if (!result.allFinite() || (result.diagonal().array() <= 0.0).any()) return false;
  *U = result;
  return true;
}

LogCholeskyParameterization::LogCholeskyParameterization() = default;

LogCholeskyParameterization::LogCholeskyParameterization(const InertialParams& reference) {
  const ConsistencyReport report = CheckConsistency(reference);
  if (!report.fully_consistent()) {
    throw std::invalid_argument("log-Cholesky reference body is not fully physically consistent: " + report.reason);
  }
  J0_ = reference.pseudo_inertia();
  if (!UpperCholesky(J0_, &U0_)) {
    throw std::invalid_argument("log-Cholesky reference body: pseudo-inertia has no Cholesky factor");
  }
  identity_reference_ = false;
}

namespace {
// The column of d pi / d theta_k for dU = v e_R e_C^T (every theta but alpha), with b = v (U J0)(:, C)
// (b = v B(C, :)^T for J = U B, B = J0 U^T): dJ = dU B + (dU B)^T = e_R b^T + b e_R^T (R < 3) has
// mass 0, h' = b_3 e_R and Sigma' = e_R b^T + b e_R^T on the 3 x 3 block, so I' = 2 b_R 1 - Sigma'.
// R is a template argument so that the choices below fold away.
template <int R>
void PerturbationColumn(const Eigen::Vector4d& b, double* c) {
  const double tr = 2.0 * b[R];
  c[pi_ix::kMass] = 0.0;
  c[pi_ix::kHx] = R == 0 ? b[3] : 0.0;
  c[pi_ix::kHy] = R == 1 ? b[3] : 0.0;
  c[pi_ix::kHz] = R == 2 ? b[3] : 0.0;
  c[pi_ix::kIxx] = R == 0 ? 0.0 : tr;
  c[pi_ix::kIyy] = R == 1 ? 0.0 : tr;
  c[pi_ix::kIzz] = R == 2 ? 0.0 : tr;
  c[pi_ix::kIxy] = R == 0 ? -b[1] : (R == 1 ? -b[0] : 0.0);
  c[pi_ix::kIyz] = R == 1 ? -b[2] : (R == 2 ? -b[1] : 0.0);
  c[pi_ix::kIxz] = R == 0 ? -b[2] : (R == 2 ? -b[0] : 0.0);
}
}  // namespace

Vector10 LogCholeskyParameterization::ToPi(const Vector10& theta, Matrix10* J_pi_theta) const {
  if (identity_reference_) return PiFromLogCholesky(theta, J_pi_theta);
  const Matrix4 U = LogCholeskyFactor(theta);
  const Matrix4 Bt = U * J0_;  // B^T for J = U B, B = J0 U^T (J0 symmetric): its columns are contiguous
  const Vector10 pi = PiFromPseudoInertia(Bt * U.transpose());
  if (J_pi_theta != nullptr) {
    // Written out, not through a 4 x 4 and PiFromPseudoInertia per column (the Jacobian is on the
    // estimator's every tick).
    Matrix10& J = *J_pi_theta;
    const double ea = U(3, 3);  // e^alpha (U = e^alpha [...; 0 0 0 1])
    J.col(kAlpha) = 2.0 * pi;
    // dU/d d_i = U(i, i) e_i e_i^T (U(i, i) = e^alpha e^{d_i}); dU/d s, t = e^alpha e_R e_C^T.
    PerturbationColumn<0>(U(0, 0) * Bt.col(0), J.col(kD1).data());
    PerturbationColumn<1>(U(1, 1) * Bt.col(1), J.col(kD2).data());
    PerturbationColumn<2>(U(2, 2) * Bt.col(2), J.col(kD3).data());
    PerturbationColumn<0>(ea * Bt.col(1), J.col(kS12).data());
    PerturbationColumn<1>(ea * Bt.col(2), J.col(kS23).data());
    PerturbationColumn<0>(ea * Bt.col(2), J.col(kS13).data());
    PerturbationColumn<0>(ea * Bt.col(3), J.col(kT1).data());
    PerturbationColumn<1>(ea * Bt.col(3), J.col(kT2).data());
    PerturbationColumn<2>(ea * Bt.col(3), J.col(kT3).data());
  }
  return pi;
}

namespace {
// A times PerturbationColumn<R>(b): b_3 A e_{h_R} + 2 b_R (the two diagonal columns of I but R's)
// - the two off-diagonal columns of I that touch R, each times the other coordinate of b.
template <int R>
Vector6 ProjectedColumn(const Matrix6x10& A, const Vector6& diagonal_pair, const Eigen::Vector4d& b) {
  constexpr int kH = pi_ix::kHx + R;
  constexpr int kOff1 = R == 0 ? pi_ix::kIxy : (R == 1 ? pi_ix::kIxy : pi_ix::kIyz);
  constexpr int kOff2 = R == 0 ? pi_ix::kIxz : (R == 1 ? pi_ix::kIyz : pi_ix::kIxz);
  constexpr int kB1 = R == 0 ? 1 : (R == 1 ? 0 : 1);
  constexpr int kB2 = R == 0 ? 2 : (R == 1 ? 2 : 0);
  return b[3] * A.col(kH) + (2.0 * b[R]) * diagonal_pair - b[kB1] * A.col(kOff1) - b[kB2] * A.col(kOff2);
}
}  // namespace

Vector10 LogCholeskyParameterization::ToPiProjected(const Vector10& theta, const Matrix6x10& A, Matrix6x10* AJ) const {
  // U as LogCholeskyFactor forms it, its four exponentials in one vector operation (Eigen's
  // packet exp: within an ulp or two of std::exp; this is the estimator's per-tick path).
  const Eigen::Array4d e = Eigen::Array4d(theta[kAlpha], theta[kAlpha] + theta[kD1], theta[kAlpha] + theta[kD2],
                                          theta[kAlpha] + theta[kD3]).exp();
  const double s = e[0];
  Matrix4 U;
  U << e[1], s * theta[kS12], s * theta[kS13], s * theta[kT1],  //
      0.0, e[2], s * theta[kS23], s * theta[kT2],                //
      0.0, 0.0, e[3], s * theta[kT3],                            //
      0.0, 0.0, 0.0, s;
  const Matrix4 Bt = identity_reference_ ? U : Matrix4(U * J0_);
  const Vector10 pi = identity_reference_ ? PiFromLogCholesky(theta, nullptr) : PiFromPseudoInertia(Bt * U.transpose());
  const double ea = U(3, 3);
  // The pairs of I's diagonal columns a perturbation of row R moves (all but R's own).
  const Vector6 pair0 = A.col(pi_ix::kIyy) + A.col(pi_ix::kIzz);
  const Vector6 pair1 = A.col(pi_ix::kIxx) + A.col(pi_ix::kIzz);
  const Vector6 pair2 = A.col(pi_ix::kIxx) + A.col(pi_ix::kIyy);
  Matrix6x10& H = *AJ;
  H.col(kAlpha).noalias() = 2.0 * (A * pi);
  H.col(kD1) = ProjectedColumn<0>(A, pair0, U(0, 0) * Bt.col(0));
  H.col(kD2) = ProjectedColumn<1>(A, pair1, U(1, 1) * Bt.col(1));
  H.col(kD3) = ProjectedColumn<2>(A, pair2, U(2, 2) * Bt.col(2));
  H.col(kS12) = ProjectedColumn<0>(A, pair0, ea * Bt.col(1));
  H.col(kS23) = ProjectedColumn<1>(A, pair1, ea * Bt.col(2));
  H.col(kS13) = ProjectedColumn<0>(A, pair0, ea * Bt.col(2));
  H.col(kT1) = ProjectedColumn<0>(A, pair0, ea * Bt.col(3));
  H.col(kT2) = ProjectedColumn<1>(A, pair1, ea * Bt.col(3));
  H.col(kT3) = ProjectedColumn<2>(A, pair2, ea * Bt.col(3));
  return pi;
}

Matrix10 LogCholeskyParameterization::ContractedHessian(const Vector10& theta, const Vector10& g) const {
  const Matrix4 G = PseudoInertiaGradient(g);  // g . pi = tr(G J)
  const Matrix4 U = LogCholeskyFactor(theta);
  const double ea = std::exp(theta[kAlpha]);
  // First derivatives of U.
  Matrix4 dU[10];
  dU[kAlpha] = U;
  const int d_index[3] = {kD1, kD2, kD3};
  for (int i = 0; i < 3; ++i) {
    dU[d_index[i]] = Matrix4::Zero();
    dU[d_index[i]](i, i) = ea * std::exp(theta[d_index[i]]);
  }
  struct Entry {
    int index, row, col;
  };
  const Entry entries[6] = {{kS12, 0, 1}, {kS23, 1, 2}, {kS13, 0, 2}, {kT1, 0, 3}, {kT2, 1, 3}, {kT3, 2, 3}};
  for (const Entry& e : entries) {
    dU[e.index] = Matrix4::Zero();
    dU[e.index](e.row, e.col) = ea;
  }
  // B_k = G dU_k J0 (so that tr(G dU_k J0 dU_l^T) = tr(B_k dU_l^T) = sum of B_k .* dU_l).
  Matrix4 B[10];
  for (int k = 0; k < 10; ++k) B[k] = G * dU[k] * J0_;
  Matrix10 H;
  for (int k = 0; k < 10; ++k) {
    for (int l = k; l < 10; ++l) {
      double value = 2.0 * B[k].cwiseProduct(dU[l]).sum();
      // Second derivatives of U: U_{alpha l} = dU_l (also U_{alpha alpha} = U = dU_alpha) and
      // U_{d_i d_i} = dU_{d_i}; tr(G U_kl J0 U^T) = sum of (G U_kl J0) .* U.
      if (k == kAlpha) value += 2.0 * B[l].cwiseProduct(U).sum();
      if (k == l && (k == kD1 || k == kD2 || k == kD3)) value += 2.0 * B[k].cwiseProduct(U).sum();
      H(k, l) = H(l, k) = value;
    }
  }
  return H;
}

bool LogCholeskyParameterization::FromPi(const Vector10& pi, Vector10* theta) const {
  if (!pi.allFinite()) return false;
  Matrix4 U1;
  if (!UpperCholesky(PseudoInertiaFromPi(pi), &U1)) return false;
  // J = U1 U1^T = U J0 U^T with J0 = U0 U0^T  =>  U = U1 U0^{-1} (upper triangular, positive diagonal).
  const Matrix4 U = identity_reference_ ? U1 : Matrix4(U0_.transpose().triangularView<Eigen::Lower>().solve(U1.transpose()).transpose());
  const double ea = U(3, 3);
  Vector10 result;
  result[kAlpha] = std::log(ea);
  result[kD1] = std::log(U(0, 0) / ea);
  result[kD2] = std::log(U(1, 1) / ea);
  result[kD3] = std::log(U(2, 2) / ea);
  result[kS12] = U(0, 1) / ea;
  result[kS23] = U(1, 2) / ea;
  result[kS13] = U(0, 2) / ea;
  result[kT1] = U(0, 3) / ea;
  result[kT2] = U(1, 3) / ea;
  result[kT3] = U(2, 3) / ea;
  if (!result.allFinite()) return false;
  *theta = result;
  return true;
}

Vector10 LogCholeskyParameterization::ThetaOf(const InertialParams& body) const {
  const ConsistencyReport report = CheckConsistency(body);
  if (!report.fully_consistent()) {
    throw std::invalid_argument("no log-Cholesky parameters: the body is not fully physically consistent: " +
                                report.reason);
  }
  Vector10 theta;
  if (!FromPi(body.vector(), &theta)) {
    throw std::invalid_argument("no log-Cholesky parameters: the pseudo-inertia has no Cholesky factor");
  }
  return theta;
}

}  // namespace inertial
