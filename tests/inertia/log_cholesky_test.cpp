#include "inertial/inertia/log_cholesky.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <Eigen/LU>
#include <limits>

#include "inertial/inertia/closed_form_bodies.hpp"
#include "inertial/inertia/consistency.hpp"
#include "inconsistent_bodies.hpp"
#include "test_support.hpp"

namespace inertial {
namespace {

using testing::CentralDifference;
using testing::RelativeError;
using testing::Rng;
using namespace theta_index;

// Reference bodies of 0.1 to 3 kg, 5 cm to 1 m. One draw per statement, the last dimension first
// and the mass last, as the x86-64 build drew SolidBox's and SolidEllipsoid's arguments (see testing::Rng).
InertialParams RandomBox(Rng& rng, const Pose& pose) {
  const double z = rng.Uniform(0.05, 1.0);
  const double y = rng.Uniform(0.05, 1.0);
  const double x = rng.Uniform(0.05, 1.0);
  return SolidBox(rng.Uniform(0.1, 3.0), x, y, z, pose);
}

InertialParams RandomEllipsoid(Rng& rng, const Pose& pose) {
  const double c = rng.Uniform(0.05, 1.0);
  const double b = rng.Uniform(0.05, 1.0);
  const double a = rng.Uniform(0.05, 1.0);
  return SolidEllipsoid(rng.Uniform(0.1, 3.0), a, b, c, pose);
}

// The closed form of pi(theta) equals pi of the matrix product U U^T (eq. 7-8), entry by entry.
TEST(LogCholesky, ClosedFormMatchesMatrixProduct) {
  Rng rng(11);
  for (int n = 0; n < 2000; ++n) {
    const Vector10 theta = rng.UniformVector<10>(-3.0, 3.0);
    const Matrix4 U = LogCholeskyFactor(theta);
    const Vector10 expected = PiFromPseudoInertia(U * U.transpose());
    const Vector10 pi = PiFromLogCholesky(theta);
    EXPECT_LT(RelativeError(pi, expected), 1e-13) << theta.transpose();
  }
}

// It is U U^T, not the printed eq. (9) (which is pi(U^T U)): m = e^{2 alpha} and h = m t.
TEST(LogCholesky, MassIsExpTwoAlphaAndFirstMomentIsMassTimesT) {
  Vector10 theta;
  theta << 0.3, -0.2, 0.1, 0.4, 0.5, -0.7, 0.9, 0.25, -0.5, 1.5;
  const Vector10 pi = PiFromLogCholesky(theta);
  const double m = std::exp(0.6);
  EXPECT_NEAR(pi[pi_index::kMass], m, 1e-14);
  EXPECT_NEAR(pi[pi_index::kHx], m * 0.25, 1e-14);
  EXPECT_NEAR(pi[pi_index::kHy], m * -0.5, 1e-14);
  EXPECT_NEAR(pi[pi_index::kHz], m * 1.5, 1e-14);
  // The printed eq. (9)'s first entry, e^{2a}(t.t + 1), would be the (4,4) entry of U^T U instead.
  const Matrix4 U = LogCholeskyFactor(theta);
  EXPECT_NEAR((U.transpose() * U)(3, 3), m * (0.25 * 0.25 + 0.25 + 1.5 * 1.5 + 1.0), 1e-12);
}

TEST(LogCholesky, JacobianMatchesCentralDifferences) {
  Rng rng(12);
  const std::function<Vector10(const Vector10&)> f = [](const Vector10& x) { return PiFromLogCholesky(x); };
  for (int n = 0; n < 500; ++n) {
    const Vector10 theta = rng.UniformVector<10>(-2.0, 2.0);
    Matrix10 J;
    PiFromLogCholesky(theta, &J);
    const Matrix10 Jfd = CentralDifference<10, 10>(f, theta);
    EXPECT_LT(RelativeError(J, Jfd), 1e-6) << theta.transpose();
  }
  // Hard points: very negative d (flat body), tiny mass.
  Vector10 flat = Vector10::Zero();
  flat[kD3] = -8.0;
  flat[kAlpha] = -6.0;
  Matrix10 J;
  PiFromLogCholesky(flat, &J);
  const Matrix10 Jfd = CentralDifference<10, 10>(f, flat, 1e-7);
  EXPECT_LT((J - Jfd).cwiseAbs().maxCoeff() / J.cwiseAbs().maxCoeff(), 1e-6);
}

TEST(LogCholesky, DeterminantHasClosedFormAndNeverVanishes) {
  Rng rng(13);
  for (int n = 0; n < 2000; ++n) {
    const Vector10 theta = rng.UniformVector<10>(-2.0, 2.0);
    Matrix10 J;
    PiFromLogCholesky(theta, &J);
    const double det = J.determinant();
    const double closed = LogCholeskyJacobianDeterminant(theta);
    EXPECT_NEAR(det / closed, 1.0, 1e-9) << theta.transpose();
    EXPECT_NE(closed, 0.0);
  }
}

// The pseudo-inertia P(pi) = [Sigma h; h^T m] in long double, from a pi stored in double (exact up to
// long double's rounding: 2^-64 on x86-64, 2^-113 on AArch64).
Eigen::Matrix<long double, 4, 4> PseudoInertiaLong(const Vector10& pi) {
  using namespace pi_index;
  const long double ixx = pi[kIxx], iyy = pi[kIyy], izz = pi[kIzz];
  const long double half_trace = 0.5L * (ixx + iyy + izz);
  Eigen::Matrix<long double, 4, 4> P;
  P << half_trace - ixx, -static_cast<long double>(pi[kIxy]), -static_cast<long double>(pi[kIxz]), pi[kHx],  //
      -static_cast<long double>(pi[kIxy]), half_trace - iyy, -static_cast<long double>(pi[kIyz]), pi[kHy],     //
      -static_cast<long double>(pi[kIxz]), -static_cast<long double>(pi[kIyz]), half_trace - izz, pi[kHz],     //
      pi[kHx], pi[kHy], pi[kHz], pi[kMass];
  return P;
}

// The log-Cholesky factor U(theta) = e^alpha [e^d1 s12 s13 t1; 0 e^d2 s23 t2; 0 0 e^d3 t3; 0 0 0 1]
// (eq. 7), in long double: an independent evaluation of the forward map for the backward-error test.
Eigen::Matrix<long double, 4, 4> FactorLong(const Vector10& theta) {
  const long double s = std::exp(static_cast<long double>(theta[kAlpha]));
  Eigen::Matrix<long double, 4, 4> U;
  U << std::exp(static_cast<long double>(theta[kD1])), theta[kS12], theta[kS13], theta[kT1],  //
      0.0L, std::exp(static_cast<long double>(theta[kD2])), theta[kS23], theta[kT2],          //
      0.0L, 0.0L, std::exp(static_cast<long double>(theta[kD3])), theta[kT3],                 //
      0.0L, 0.0L, 0.0L, 1.0L;
  return s * U;
}

// theta -> pi -> theta over 10^4 seeded theta with |theta_i| <= 5. Where the inverse map is well
// conditioned the round trip must be accurate; elsewhere (e.g. e^{d} = e^-5 beside shears and offsets
// of 5, where storing pi in double alone moves theta by more than 1e-9) the right claim is backward
// stability: the theta returned is exactly the log-Cholesky of a pi within the rounding bound of the
// arithmetic FromPi does. That bound, derived term by term (u = 2^-53, gamma_k = k u / (1 - k u)):
//  1. Sigma = tr(I)/2 - I from the stored pi: two additions and a subtraction on the diagonal, so
//     |dSigma_ii| <= gamma_3 (|Ixx| + |Iyy| + |Izz|); off-diagonal entries, h and m are copied exactly.
//  2. The Cholesky factor U1 of the 4x4 P (Higham, "Accuracy and Stability of Numerical Algorithms",
//     2nd ed., Thm 10.3): U1 U1^T = P + dP with |dP| <= gamma_{n+1} |U1| |U1|^T, n = 4. Holds for any
//     order of the inner products and with or without fused multiply-adds (x86 and Arm alike).
//  3. theta from U1: alpha = log U1_33, d_i = log(U1_ii / e^alpha), s, t = U1_ij / e^alpha. With log
//     within one ulp (2u relative) and each division rounded once, exp of the stored theta rebuilds
//     every entry of U1 to a relative rho = u (1 + 2|alpha| + 2 max|d_i|) (first order); the rebuilt
//     U~ then has |U~ U~^T - U1 U1^T| <= (2 rho + rho^2) |U1| |U1|^T.
//  4. This test's own long double arithmetic: below 64 u_long |U~| |U~|^T, negligible beside u.
// So |U~ U~^T - P(pi)| <= (gamma_5 + 2 rho + rho^2)(1 + rho)^2 |U~| |U~|^T + diag(1.+3.) entrywise,
// the (1 + rho)^2 turning |U1| into |U~|. No constant here was measured; a wrong index or an unstable
// inverse (normal equations, eigen-decomposition) exceeds it by orders of magnitude.
TEST(LogCholesky, RoundTripThetaPiTheta) {
  Rng rng(14);
  const LogCholeskyParameterization param;
  const double u = 0.5 * std::numeric_limits<double>::epsilon();
  const long double u_long = 0.5L * std::numeric_limits<long double>::epsilon();
  const auto gamma = [u](int k) { return k * u / (1.0 - k * u); };
  int well_conditioned = 0;
  double worst_well_conditioned = 0.0, worst_backward_ratio = 0.0;
  for (int n = 0; n < 10000; ++n) {
    const Vector10 theta = rng.UniformVector<10>(-5.0, 5.0);
    Matrix10 J;
    const Vector10 pi = PiFromLogCholesky(theta, &J);
    Vector10 back;
    ASSERT_TRUE(param.FromPi(pi, &back)) << theta.transpose();

    // Backward stability, everywhere.
    const Eigen::Matrix<long double, 4, 4> U = FactorLong(back);
    const Eigen::Matrix<long double, 4, 4> residual = U * U.transpose() - PseudoInertiaLong(pi);
    const Eigen::Matrix<long double, 4, 4> magnitude = U.cwiseAbs() * U.cwiseAbs().transpose();
    const double max_d = back.segment<3>(kD1).cwiseAbs().maxCoeff();
    const double rho = u * (1.0 + 2.0 * std::abs(back[kAlpha]) + 2.0 * max_d);
    const double factor = (gamma(5) + 2.0 * rho + rho * rho) * (1.0 + rho) * (1.0 + rho);
    const double trace_magnitude = std::abs(pi[pi_index::kIxx]) + std::abs(pi[pi_index::kIyy]) + std::abs(pi[pi_index::kIzz]);
    for (int i = 0; i < 4; ++i) {
      for (int j = 0; j < 4; ++j) {
        long double bound = factor * magnitude(i, j) + 64.0L * u_long * magnitude(i, j);
        if (i == j && i < 3) bound += gamma(3) * trace_magnitude;
        EXPECT_LE(std::abs(residual(i, j)), bound) << "P(" << i << "," << j << ") at theta " << theta.transpose();
        worst_backward_ratio = std::max(worst_backward_ratio, static_cast<double>(std::abs(residual(i, j)) / bound));
      }
    }

    // Forward accuracy where the inverse is well conditioned: the first-order bound of the error that
    // storing pi in double alone causes, |J_pi_theta^{-1}| |pi| u, is below 1e-11.
    const Vector10 inherent = J.inverse().cwiseAbs() * pi.cwiseAbs() * u;
    double err = 0.0, bound = 0.0;
    for (int i = 0; i < 10; ++i) {
      const double scale = std::max(1.0, std::abs(theta[i]));
      err = std::max(err, std::abs(back[i] - theta[i]) / scale);
      bound = std::max(bound, inherent[i] / scale);
    }
    if (bound <= 1e-11) {
      ++well_conditioned;
      worst_well_conditioned = std::max(worst_well_conditioned, err);
      EXPECT_LT(err, 1e-9) << theta.transpose();
    }
  }
  // A good part of the box is well conditioned: the forward check must not be vacuous.
  EXPECT_GT(well_conditioned, 3000);  // 3712 of 10^4 with seed 14
  RecordProperty("well_conditioned_samples", well_conditioned);
  RecordProperty("worst_error_well_conditioned", std::to_string(worst_well_conditioned));
  RecordProperty("worst_backward_error_over_bound", std::to_string(worst_backward_ratio));
  std::printf("well conditioned: %d, worst forward error there %.3g, worst backward error / bound %.3g\n",
              well_conditioned, worst_well_conditioned, worst_backward_ratio);
}

// Moderate theta: the round trip is accurate to 1e-9 for every sample.
TEST(LogCholesky, RoundTripModerateThetaEverywhere) {
  Rng rng(19);
  const LogCholeskyParameterization param;
  for (int n = 0; n < 10000; ++n) {
    const Vector10 theta = rng.UniformVector<10>(-2.0, 2.0);
    Vector10 back;
    ASSERT_TRUE(param.FromPi(param.ToPi(theta), &back));
    EXPECT_LT(RelativeError(back, theta), 1e-9) << theta.transpose();
  }
}

// pi -> theta -> pi for consistent bodies: the forward map is well conditioned.
TEST(LogCholesky, RoundTripPiThetaPi) {
  Rng rng(20);
  const LogCholeskyParameterization param;
  for (int n = 0; n < 10000; ++n) {
    const Pose pose = rng.RandomPose<Pose>(1.0);
    // One draw per statement, in the order the x86-64 build drew them (see testing::Rng).
    const Vector3 L = rng.UniformVector<3>(1e-4, 1.0);
    const InertialParams body = BodyFromSecondMoments(rng.Uniform(0.01, 10.0), L, pose);
    const Vector10 theta = param.ThetaOf(body);
    EXPECT_LT(RelativeError(param.ToPi(theta), body.vector()), 1e-12);
  }
}

TEST(LogCholesky, EveryThetaGivesAFullyConsistentBody) {
  Rng rng(15);
  for (int n = 0; n < 5000; ++n) {
    const Vector10 theta = rng.UniformVector<10>(-3.0, 3.0);
    const ConsistencyReport report = CheckConsistency(InertialParams::FromVector(PiFromLogCholesky(theta)));
    EXPECT_TRUE(report.fully_consistent()) << report.reason << " at " << theta.transpose();
  }
}

TEST(LogCholesky, YieldsConsistentBodyForEveryFiniteThetaThatDoesNotOverflow) {
  const LogCholeskyParameterization param;
  Vector10 thin = Vector10::Zero();
  thin[kD3] = -40.0;  // a body e^-40 thin: consistent, though its numerical margins round to zero
  EXPECT_TRUE(param.YieldsConsistentBody(thin));
  EXPECT_FALSE(CheckConsistency(InertialParams::FromVector(param.ToPi(thin))).fully_consistent());
  Vector10 huge = Vector10::Zero();
  huge[kAlpha] = 400.0;  // e^800 overflows
  EXPECT_FALSE(param.YieldsConsistentBody(huge));
  huge[kAlpha] = std::nan("");
  EXPECT_FALSE(param.YieldsConsistentBody(huge));
}

TEST(LogCholesky, InverseRefusesInconsistentBodies) {
  const LogCholeskyParameterization param;
  Vector10 theta = Vector10::Constant(42.0);
  // A thin plate: Dz = Dx + Dy (not fully consistent).
  const Vector10 plate = BodyFromSecondMoments(1.0, Vector3(0.1, 0.2, 0.0)).vector();
  EXPECT_THROW(param.ThetaOf(InertialParams::FromVector(plate)), std::invalid_argument);
  // Negative mass.
  Vector10 negative = SolidBox(1.0, 0.1, 0.2, 0.3).vector();
  negative[pi_index::kMass] = -1.0;
  EXPECT_FALSE(param.FromPi(negative, &theta));
  EXPECT_EQ(theta, Vector10::Constant(42.0));  // untouched
  try {
    param.ThetaOf(InertialParams::FromVector(negative));
    FAIL() << "expected a throw";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("mass not positive"), std::string::npos) << e.what();
  }
  Vector10 nan = SolidBox(1.0, 0.1, 0.2, 0.3).vector();
  nan[pi_index::kIxy] = std::nan("");
  EXPECT_FALSE(param.FromPi(nan, &theta));
  // The shared set: ThetaOf refuses every one (FromPi alone has no tolerance, so a plate that is
  // flat only up to rounding may factor; ThetaOf applies CheckConsistency first).
  for (const Vector10& pi : testing::InconsistentBodies(21)) {
    EXPECT_THROW(param.ThetaOf(InertialParams::FromVector(pi)), std::invalid_argument) << pi.transpose();
  }
}

// Eq. (11): theta = 0 is the reference body; t translates it, alpha scales its density, d stretches it.
// What `inertial simulate --perturb P` promises of the true bodies: with U = e^alpha [A t; 0 1]
// (LogCholeskyFactor), pi(theta) relative to a reference of mass m0 and COM c0 has mass
// e^{2 alpha} m0 and COM A c0 + t (J = U J0 U^T: h = e^{2 alpha} (A h0 + m0 t)).
TEST(LogCholeskyRelative, MassAndComOfAPerturbedBody) {
  Rng rng(17);
  for (int n = 0; n < 200; ++n) {
    const Pose pose = rng.RandomPose<Pose>(0.5);  // before the box, as on x86-64 (the last argument; see RandomBox)
    const InertialParams reference = RandomBox(rng, pose);
    const LogCholeskyParameterization param(reference);
    const Vector10 theta = rng.UniformVector<10>(-0.2, 0.2);
    const InertialParams body = InertialParams::FromVector(param.ToPi(theta));
    const Matrix4 U = LogCholeskyFactor(theta);
    const double e_alpha = std::exp(theta[kAlpha]);
    const Matrix3 A = U.topLeftCorner<3, 3>() / e_alpha;
    const Vector3 t = U.topRightCorner<3, 1>() / e_alpha;
    EXPECT_NEAR(body.mass(), e_alpha * e_alpha * reference.mass(), 1e-14 * body.mass());
    EXPECT_LT((body.com() - (A * reference.com() + t)).norm(), 1e-13);
    EXPECT_LT((t - theta.tail<3>()).norm(), 1e-15);  // t is theta's last three entries, in metres
  }
}

TEST(LogCholeskyRelative, PhysicalMeaningOfTheParameters) {
  Rng rng(16);
  for (int n = 0; n < 200; ++n) {
    const Pose pose = rng.RandomPose<Pose>(0.5);
    const InertialParams reference = RandomBox(rng, pose);
    const LogCholeskyParameterization param(reference);
    EXPECT_LT(RelativeError(param.ThetaOf(reference), Vector10::Zero()), 1e-12);
    EXPECT_LT(RelativeError(param.ToPi(Vector10::Zero()), reference.vector()), 1e-13);

    // Translate by p: theta = [0, 0, 0, 0, 0, 0, 0, p].
    const Vector3 p = rng.UniformVector<3>(-1.0, 1.0);
    const InertialParams moved = reference.Transformed(Matrix3::Identity(), p);
    Vector10 expected = Vector10::Zero();
    expected.segment<3>(kT1) = p;
    EXPECT_LT(RelativeError(param.ThetaOf(moved), expected), 1e-10);

    // Density scaled by k: alpha = log(k) / 2.
    const double k = rng.Uniform(0.1, 10.0);
    expected.setZero();
    expected[kAlpha] = 0.5 * std::log(k);
    EXPECT_LT(RelativeError(param.ThetaOf(InertialParams::FromVector(k * reference.vector())), expected), 1e-10);
  }
  // Stretch along z by e^d for a box in its own frame: d3 = d (density unchanged, so mass scales by e^d
  // too: alpha = d / 2).
  const double d = 0.4;
  const InertialParams box = SolidBox(2.0, 0.3, 0.4, 0.5);
  const InertialParams stretched = SolidBox(2.0 * std::exp(d), 0.3, 0.4, 0.5 * std::exp(d));
  Vector10 expected = Vector10::Zero();
  expected[kAlpha] = d / 2.0;
  expected[kD3] = d;  // U = e^{d/2} diag(1, 1, e^d, 1): alpha = d/2, d1 = d2 = 0, d3 = d
  EXPECT_LT(RelativeError(LogCholeskyParameterization(box).ThetaOf(stretched), expected), 1e-12);
}

TEST(LogCholeskyRelative, JacobianMatchesCentralDifferencesAndRoundTrips) {
  Rng rng(17);
  for (int n = 0; n < 200; ++n) {
    const Pose pose = rng.RandomPose<Pose>(0.5);
    const InertialParams reference = RandomEllipsoid(rng, pose);
    const LogCholeskyParameterization param(reference);
    const Vector10 theta = rng.UniformVector<10>(-2.0, 2.0);
    Matrix10 J;
    const Vector10 pi = param.ToPi(theta, &J);
    const std::function<Vector10(const Vector10&)> f = [&](const Vector10& x) { return param.ToPi(x); };
    EXPECT_LT(RelativeError(J, CentralDifference<10, 10>(f, theta)), 1e-6);
    Vector10 back;
    ASSERT_TRUE(param.FromPi(pi, &back));
    EXPECT_LT(RelativeError(back, theta), 1e-9);
  }
}

// The projected Jacobian A J against central differences of A pi(theta) (and pi against ToPi), for
// the identity reference and random reference bodies, with a random 6 x 10 A.
TEST(LogCholeskyRelative, ProjectedJacobianMatchesCentralDifferencesOfTheRegressorTimesPi) {
  Rng rng(19);
  for (int n = 0; n < 100; ++n) {
    const Pose pose = rng.RandomPose<Pose>(0.5);
    const LogCholeskyParameterization param =
        n % 4 == 0 ? LogCholeskyParameterization() : LogCholeskyParameterization(RandomEllipsoid(rng, pose));
    const Vector10 theta = rng.UniformVector<10>(-1.5, 1.5);
    Matrix6x10 A;
    for (int c = 0; c < 10; ++c) A.col(c) = rng.UniformVector<6>(-2.0, 2.0);
    Matrix6x10 AJ;
    const Vector10 pi = param.ToPiProjected(theta, A, &AJ);
    EXPECT_LT(RelativeError(pi, param.ToPi(theta)), 1e-14);
    const std::function<Vector6(const Vector10&)> f = [&](const Vector10& x) { return Vector6(A * param.ToPi(x)); };
    EXPECT_LT(RelativeError(AJ, CentralDifference<6, 10>(f, theta)), 1e-6) << "draw " << n;
  }
}

// The Hessian of g . pi(theta) against central differences of the (independently tested) exact
// Jacobian, for the identity reference and for random reference bodies; and symmetric.
TEST(LogCholeskyRelative, ContractedHessianMatchesDifferencesOfTheJacobian) {
  Rng rng(21);
  for (int n = 0; n < 200; ++n) {
    const Pose pose = rng.RandomPose<Pose>(0.5);
    const LogCholeskyParameterization param =
        n % 4 == 0 ? LogCholeskyParameterization()
                   : LogCholeskyParameterization(RandomEllipsoid(rng, pose));
    const Vector10 theta = rng.UniformVector<10>(-1.5, 1.5);
    const Vector10 g = rng.UniformVector<10>(-1.0, 1.0);
    const std::function<Vector10(const Vector10&)> gradient = [&](const Vector10& x) {
      Matrix10 J;
      param.ToPi(x, &J);
      return Vector10(J.transpose() * g);
    };
    const Matrix10 H = param.ContractedHessian(theta, g);
    EXPECT_LT(RelativeError(H, CentralDifference<10, 10>(gradient, theta)), 1e-6) << n;
    EXPECT_LT((H - H.transpose()).norm(), 1e-12 * H.norm());
  }
}

// The general path (eq. 11 with J0 = 1 given as a body) equals the closed form.
TEST(LogCholeskyRelative, IdentityReferenceAsABodyEqualsClosedForm) {
  const LogCholeskyParameterization general(InertialParams::FromPseudoInertia(Matrix4::Identity()));
  ASSERT_FALSE(general.has_identity_reference());
  Rng rng(18);
  for (int n = 0; n < 200; ++n) {
    const Vector10 theta = rng.UniformVector<10>(-2.0, 2.0);
    Matrix10 J_closed, J_general;
    const Vector10 closed = PiFromLogCholesky(theta, &J_closed);
    EXPECT_LT(RelativeError(general.ToPi(theta, &J_general), closed), 1e-13);
    EXPECT_LT(RelativeError(J_general, J_closed), 1e-12);
  }
}

TEST(LogCholeskyRelative, RejectsDegenerateReference) {
  EXPECT_THROW(LogCholeskyParameterization(BodyFromSecondMoments(1.0, Vector3(0.1, 0.0, 0.0))), std::invalid_argument);
}

}  // namespace
}  // namespace inertial
