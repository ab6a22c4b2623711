#include "inertial/inertia/exponential_parameterization.hpp"

#include <gtest/gtest.h>

#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <unsupported/Eigen/MatrixFunctions>
#include <vector>

#include "inertial/inertia/closed_form_bodies.hpp"
#include "inertial/inertia/consistency.hpp"
#include "inertial/inertia/log_cholesky.hpp"
#include "inconsistent_bodies.hpp"
#include "test_support.hpp"

namespace inertial {
namespace {

using testing::CentralDifference;
using testing::RelativeError;
using testing::Rng;
using namespace exponential_index;

using Matrix8 = Eigen::Matrix<double, 8, 8>;

// The (row, col) of Q in each slot of x, as the specification writes it:
// x = [Q33, Q03, Q13, Q23, Q00, Q11, Q22, Q01, Q12, Q02] (kept here independently of the header).
constexpr int kSlotRow[10] = {3, 0, 1, 2, 0, 1, 2, 0, 1, 0};
constexpr int kSlotCol[10] = {3, 3, 3, 3, 0, 1, 2, 1, 2, 2};

// The symmetric unit matrix of slot k.
Matrix4 SlotUnit(int k) {
  Matrix4 E = Matrix4::Zero();
  E(kSlotRow[k], kSlotCol[k]) = 1.0;
  E(kSlotCol[k], kSlotRow[k]) = 1.0;
  return E;
}

Matrix4 QOf(const Vector10& x) {
  Matrix4 Q = Matrix4::Zero();
  for (int k = 0; k < 10; ++k) {
    Q(kSlotRow[k], kSlotCol[k]) = x[k];
    Q(kSlotCol[k], kSlotRow[k]) = x[k];
  }
  return Q;
}

Vector10 XOf(const Matrix4& Q) {
  Vector10 x;
  for (int k = 0; k < 10; ++k) x[k] = Q(kSlotRow[k], kSlotCol[k]);
  return x;
}

// exp(Q) by Eigen's Pade scaling-and-squaring (unsupported/MatrixFunctions): independent reference.
Matrix4 ReferenceExp(const Matrix4& Q) { return Q.exp(); }

// The Frechet derivative of exp at Q in direction E from the block-triangular identity
// exp([[Q, E], [0, Q]]) = [[exp(Q), L(Q, E)], [0, exp(Q)]] (Higham 2008, Thm. 3.6 / Mathias 1996).
Matrix4 ReferenceExpDerivative(const Matrix4& Q, const Matrix4& E) {
  Matrix8 B = Matrix8::Zero();
  B.topLeftCorner<4, 4>() = Q;
  B.topRightCorner<4, 4>() = E;
  B.bottomRightCorner<4, 4>() = Q;
  const Matrix8 expB = B.exp();
  return expB.topRightCorner<4, 4>();
}

// The exact J_pi_x from the reference derivative (pi is linear in J).
Matrix10 ReferenceJacobian(const Vector10& x) {
  Matrix10 J;
  for (int k = 0; k < 10; ++k) J.col(k) = PiFromPseudoInertia(ReferenceExpDerivative(QOf(x), SlotUnit(k)));
  return J;
}

Matrix4 RandomOrthogonal(Rng& rng) {
  Matrix4 A;
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < 4; ++j) A(i, j) = rng.Normal();
  }
  const Eigen::HouseholderQR<Matrix4> qr(A);
  return qr.householderQ();
}

// x of Q = V diag(l) V^T for a random orthogonal V.
Vector10 WithEigenvalues(Rng& rng, const Vector4& l) {
  const Matrix4 V = RandomOrthogonal(rng);
  return XOf(V * l.asDiagonal() * V.transpose());
}

// A random fully consistent body: mass, COM, uniformly random rotation, second moments.
InertialParams RandomBody(Rng& rng) {
  const Pose pose = rng.RandomPose<Pose>(1.0);
  const double m = rng.Uniform(0.1, 10.0);
  return BodyFromSecondMoments(m, m * rng.UniformVector<3>(1e-3, 0.5), pose);
}

// Points where the eigen-decomposition is degenerate or nearly so, and a wide spread.
std::vector<Vector10> HardPoints(Rng& rng) {
  std::vector<Vector10> points;
  points.push_back(Vector10::Zero());                                   // Q = 0: one 4-fold eigenvalue
  points.push_back(XOf(Vector4(0.3, 0.3, 0.3, -0.7).asDiagonal()));     // diag(a, a, a, b)
  points.push_back(XOf(Vector4(-1.2, 0.5, 0.5, 0.5).asDiagonal()));     // diag(b, a, a, a)
  points.push_back(WithEigenvalues(rng, Vector4(0.4, 0.4, 0.4, 1.1)));  // 3-fold, rotated
  points.push_back(WithEigenvalues(rng, Vector4(-0.5, -0.5, 0.8, 0.8)));
  points.push_back(WithEigenvalues(rng, Vector4(0.2, 0.2 + 1e-13, 0.2 + 2e-13, 0.9)));  // nearly repeated
  points.push_back(WithEigenvalues(rng, Vector4(0.2, 0.2 + 1e-9, 0.7, 0.7 + 1e-7)));
  points.push_back(WithEigenvalues(rng, Vector4(-6.0, -1.0, 2.0, 6.0)));  // wide spread
  return points;
}

// ---------------------------------------------------------------------------------------------
// The matrix exponential and logarithm.

TEST(ExponentialMap, SymmetricExpMatchesPadeReference) {
  Rng rng(201);
  for (int n = 0; n < 2000; ++n) {
    const Matrix4 Q = QOf(rng.UniformVector<10>(-2.0, 2.0));
    EXPECT_LT(RelativeError(SymmetricMatrixExp(Q), ReferenceExp(Q)), 1e-13) << Q;
  }
  for (const Vector10& x : HardPoints(rng)) {
    EXPECT_LT(RelativeError(SymmetricMatrixExp(QOf(x)), ReferenceExp(QOf(x))), 1e-13) << x.transpose();
  }
  EXPECT_LT(RelativeError(SymmetricMatrixExp(Matrix4::Zero()), Matrix4::Identity()), 1e-15);
  const Matrix4 D = Vector4(0.3, 0.3, 0.3, -0.7).asDiagonal();
  EXPECT_LT(
      RelativeError(SymmetricMatrixExp(D), Matrix4(Vector4(0.3, 0.3, 0.3, -0.7).array().exp().matrix().asDiagonal())),
      1e-15);
}

TEST(ExponentialMap, LogInvertsExp) {
  Rng rng(202);
  for (int n = 0; n < 2000; ++n) {
    const Matrix4 Q = QOf(rng.UniformVector<10>(-2.0, 2.0));
    Matrix4 back;
    ASSERT_TRUE(SymmetricMatrixLog(ReferenceExp(Q), &back));
    EXPECT_LT(RelativeError(back, Q), 1e-11) << Q;
  }
  // Not positive definite, or not finite: refused, output untouched.
  Matrix4 out = Matrix4::Constant(7.0);
  EXPECT_FALSE(SymmetricMatrixLog(Vector4(1.0, 2.0, 0.0, 3.0).asDiagonal().toDenseMatrix(), &out));
  EXPECT_FALSE(SymmetricMatrixLog(Vector4(1.0, 2.0, -1.0, 3.0).asDiagonal().toDenseMatrix(), &out));
  Matrix4 nan = Matrix4::Identity();
  nan(1, 2) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(SymmetricMatrixLog(nan, &out));
  EXPECT_EQ(out, Matrix4::Constant(7.0));
}

// ---------------------------------------------------------------------------------------------
// pi(x) and its Jacobian.

// Each slot of x is the entry of Q at the position whose entry of J pi holds in the same slot.
TEST(ExponentialParameterization, SlotsHoldTheEntriesOfQInPisOrder) {
  const ExponentialParameterization param;
  EXPECT_EQ(param.name(), "exponential");
  // x = 0: the unit body J = 1 (1 kg at the origin, rotational inertia 2 kg m^2 about each axis).
  Vector10 unit;
  unit << 1.0, 0.0, 0.0, 0.0, 2.0, 2.0, 2.0, 0.0, 0.0, 0.0;
  EXPECT_LT(RelativeError(param.ToPi(Vector10::Zero()), unit), 1e-15);
  // One off-diagonal slot: exp(t (E03 + E30)) has cosh t at (0,0) and (3,3), sinh t at (0,3).
  const double t = 0.7;
  Vector10 x = Vector10::Zero();
  x[kQ03] = t;
  Vector10 expected;
  expected << std::cosh(t), std::sinh(t), 0.0, 0.0, 2.0, 1.0 + std::cosh(t), 1.0 + std::cosh(t), 0.0, 0.0, 0.0;
  EXPECT_LT(RelativeError(param.ToPi(x), expected), 1e-14);
  // One diagonal slot: exp(t E33) scales the mass only.
  x.setZero();
  x[kQ33] = t;
  expected = unit;
  expected[pi_index::kMass] = std::exp(t);
  EXPECT_LT(RelativeError(param.ToPi(x), expected), 1e-14);
  // Every slot, against the closed form exp(t E) = 1 + (cosh t - 1)(E^2) + sinh t E for E the
  // symmetric unit of an off-diagonal slot (E^3 = E), and 1 + (e^t - 1) E on the diagonal.
  for (int k = 0; k < 10; ++k) {
    x.setZero();
    x[k] = t;
    const Matrix4 E = SlotUnit(k);
    const Matrix4 K = kSlotRow[k] == kSlotCol[k]
                          ? Matrix4(Matrix4::Identity() + std::expm1(t) * E)
                          : Matrix4(Matrix4::Identity() + (std::cosh(t) - 1.0) * E * E + std::sinh(t) * E);
    EXPECT_LT(RelativeError(param.ToPi(x), PiFromPseudoInertia(K)), 1e-14) << "slot " << k;
    EXPECT_EQ(SymmetricFromExponentialParameters(x), Matrix4(t * E)) << "slot " << k;
    EXPECT_EQ(ExponentialParametersFromSymmetric(t * E), x) << "slot " << k;
  }
}

TEST(ExponentialParameterization, ToPiMatchesPadeReference) {
  const ExponentialParameterization param;
  Rng rng(203);
  for (int n = 0; n < 2000; ++n) {
    const Vector10 x = rng.UniformVector<10>(-2.0, 2.0);
    EXPECT_LT(RelativeError(param.ToPi(x), PiFromPseudoInertia(ReferenceExp(QOf(x)))), 1e-13) << x.transpose();
  }
}

TEST(ExponentialParameterization, JacobianMatchesFrechetReferenceAndCentralDifferences) {
  const ExponentialParameterization param;
  const std::function<Vector10(const Vector10&)> f = [&](const Vector10& x) { return param.ToPi(x); };
  Rng rng(204);
  std::vector<Vector10> points = HardPoints(rng);
  for (int n = 0; n < 300; ++n) points.push_back(rng.UniformVector<10>(-2.0, 2.0));
  for (const Vector10& x : points) {
    Matrix10 J;
    const Vector10 pi = param.ToPi(x, &J);
    EXPECT_EQ(pi, param.ToPi(x));  // asking for J does not change pi
    EXPECT_LT(RelativeError(J, CentralDifference<10, 10>(f, x)), 1e-6) << x.transpose();
    EXPECT_LT(RelativeError(J, ReferenceJacobian(x)), 1e-12) << x.transpose();
  }
  // At Q = 0, G = 1: column k is pi of the slot's symmetric unit matrix, exactly.
  Matrix10 J0;
  param.ToPi(Vector10::Zero(), &J0);
  for (int k = 0; k < 10; ++k) EXPECT_EQ(J0.col(k), PiFromPseudoInertia(SlotUnit(k))) << "slot " << k;
}

// Section IV-A: no singularities. det(J_pi_x) = -2 prod_{i<=j} G_ij, never zero.
TEST(ExponentialParameterization, JacobianDeterminantHasClosedFormAndNeverVanishes) {
  const ExponentialParameterization param;
  Rng rng(205);
  std::vector<Vector10> points = HardPoints(rng);
  for (int n = 0; n < 2000; ++n) points.push_back(rng.UniformVector<10>(-2.0, 2.0));
  for (const Vector10& x : points) {
    Matrix10 J;
    param.ToPi(x, &J);
    const double closed = ExponentialJacobianDeterminant(x);
    EXPECT_NEAR(J.determinant() / closed, 1.0, 1e-9) << x.transpose();
    EXPECT_LT(closed, 0.0);
  }
  // At Q = 0 every G_ij is 1.
  EXPECT_NEAR(ExponentialJacobianDeterminant(Vector10::Zero()), -2.0, 1e-15);
}

// ---------------------------------------------------------------------------------------------
// Consistency and the inverse.

TEST(ExponentialParameterization, EveryXGivesAFullyConsistentBody) {
  const ExponentialParameterization param;
  Rng rng(206);
  for (int n = 0; n < 5000; ++n) {
    const Vector10 x = rng.UniformVector<10>(-1.5, 1.5);
    const ConsistencyReport report = CheckConsistency(InertialParams::FromVector(param.ToPi(x)));
    EXPECT_TRUE(report.fully_consistent()) << report.reason << " at " << x.transpose();
  }
}

// Consistent by construction for every finite x, also where the numerical check cannot tell.
TEST(ExponentialParameterization, YieldsConsistentBodyForEveryFiniteX) {
  const ExponentialParameterization param;
  Rng rng(211);
  for (int n = 0; n < 1000; ++n) EXPECT_TRUE(param.YieldsConsistentBody(rng.UniformVector<10>(-3.0, 3.0)));
  // A body 1e-17 thin along z: consistent by construction, margins below CheckConsistency's.
  Vector10 thin = Vector10::Zero();
  thin[kQ22] = -40.0;
  EXPECT_TRUE(param.YieldsConsistentBody(thin));
  EXPECT_FALSE(IsPhysicallyConsistent(InertialParams::FromVector(param.ToPi(thin))));
  Vector10 bad = Vector10::Zero();
  bad[kQ12] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(param.YieldsConsistentBody(bad));
  bad[kQ12] = 0.0;
  bad[kQ33] = 800.0;  // e^800 overflows
  EXPECT_FALSE(param.YieldsConsistentBody(bad));
}

TEST(ExponentialParameterization, RoundTripPiXPi) {
  const ExponentialParameterization param;
  Rng rng(207);
  std::vector<InertialParams> bodies;
  for (int n = 0; n < 5000; ++n) bodies.push_back(RandomBody(rng));
  // Bodies with repeated eigenvalues of J: the unit body, spheres at the origin, cylinders.
  bodies.push_back(InertialParams::FromPseudoInertia(Matrix4::Identity()));
  for (int n = 0; n < 50; ++n) {
    Pose pose;
    // One draw per statement, in the order the x86-64 build drew them (see testing::Rng).
    const double radius = rng.Uniform(0.05, 1.0);
    bodies.push_back(SolidSphere(rng.Uniform(0.1, 5.0), radius, pose));
    pose.R_BC = rng.Rotation();
    pose.p_BoCo_B = rng.UniformVector<3>(-1.0, 1.0);
    // One draw per statement, in the order the x86-64 build drew them (see testing::Rng).
    const double length = rng.Uniform(0.1, 1.0);
    const double cylinder_radius = rng.Uniform(0.05, 0.5);
    bodies.push_back(SolidCylinder(rng.Uniform(0.1, 5.0), cylinder_radius, length, pose));
  }
  double worst = 0.0;
  for (const InertialParams& body : bodies) {
    const Vector10& pi = body.vector();
    Vector10 x;
    ASSERT_TRUE(param.FromPi(pi, &x)) << pi.transpose();
    const double err = RelativeError(param.ToPi(x), pi);
    worst = std::max(worst, err);
    EXPECT_LT(err, 1e-10) << pi.transpose();
  }
  RecordProperty("worst_relative_error", std::to_string(worst));
  // x = log of the unit body's J = 1 is 0.
  Vector10 x;
  ASSERT_TRUE(param.FromPi(InertialParams::FromPseudoInertia(Matrix4::Identity()).vector(), &x));
  EXPECT_LT(x.cwiseAbs().maxCoeff(), 1e-15);
}

// The map is one-to-one: x -> pi -> x recovers x.
TEST(ExponentialParameterization, RoundTripXPiX) {
  const ExponentialParameterization param;
  Rng rng(208);
  std::vector<Vector10> points = HardPoints(rng);
  for (int n = 0; n < 5000; ++n) points.push_back(rng.UniformVector<10>(-1.5, 1.5));
  for (const Vector10& x : points) {
    Vector10 back;
    ASSERT_TRUE(param.FromPi(param.ToPi(x), &back)) << x.transpose();
    EXPECT_LT(RelativeError(back, x), 1e-9) << x.transpose();
  }
}

TEST(ExponentialParameterization, FromPiRefusesInconsistentBodiesAndLeavesXUntouched) {
  const ExponentialParameterization param;
  const Vector10 sentinel = Vector10::Constant(42.0);
  Vector10 x = sentinel;
  const std::vector<Vector10> refused = testing::InconsistentBodies(209);
  for (const Vector10& pi : refused) {
    EXPECT_FALSE(CheckConsistency(InertialParams::FromVector(pi)).fully_consistent());
    EXPECT_FALSE(param.FromPi(pi, &x)) << pi.transpose();
    EXPECT_EQ(x, sentinel);
  }
}

// The exponential map and the log-Cholesky map (Section IV-B) share the unit reference body and
// describe the same set C: a body found by one is reproduced by the other.
TEST(ExponentialParameterization, AgreesWithLogCholeskyOnTheSetOfConsistentBodies) {
  const ExponentialParameterization exponential;
  const LogCholeskyParameterization log_cholesky;
  EXPECT_LT(RelativeError(exponential.ToPi(Vector10::Zero()), log_cholesky.ToPi(Vector10::Zero())), 1e-15);
  Rng rng(210);
  for (int n = 0; n < 1000; ++n) {
    const Vector10 pi = log_cholesky.ToPi(rng.UniformVector<10>(-1.0, 1.0));
    Vector10 x;
    ASSERT_TRUE(exponential.FromPi(pi, &x));
    EXPECT_LT(RelativeError(exponential.ToPi(x), pi), 1e-10);
  }
}

}  // namespace
}  // namespace inertial
