#include "inertial/inertia/eigenvalue_parameterization.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>
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
using namespace phi_index;

const double kPi = std::acos(-1.0);

// R = exp(S(beta)) from Eigen's angle-axis (independent of the code under test).
Matrix3 AngleAxisRotation(const Vector3& beta) {
  const double angle = beta.norm();
  if (angle == 0.0) return Matrix3::Identity();
  return Eigen::AngleAxisd(angle, beta / angle).toRotationMatrix();
}

// dR/dbeta_k in the form of Gallego & Yezzi (2015), valid for beta != 0:
// (beta_k S(beta) + S(beta x ((1 - R) e_k))) R / |beta|^2.
Matrix3 GallegoYezziDerivative(const Vector3& beta, int k) {
  const Matrix3 R = AngleAxisRotation(beta);
  const Vector3 e = Vector3::Unit(k);
  return (beta[k] * Skew(beta) + Skew(beta.cross((Matrix3::Identity() - R) * e))) * R / beta.squaredNorm();
}

// The left Jacobian of SO(3) in the form sin t/t 1 + (1 - sin t/t) a a^T + (1 - cos t)/t S(a),
// t = |beta|, a = beta/t (Barfoot 2017); beta != 0.
Matrix3 LeftJacobian(const Vector3& beta) {
  const double t = beta.norm();
  const Vector3 a = beta / t;
  return std::sin(t) / t * Matrix3::Identity() + (1.0 - std::sin(t) / t) * a * a.transpose() +
         (1.0 - std::cos(t)) / t * Skew(a);
}

Vector10 Phi(double m, const Vector3& c, const Vector3& beta, const Vector3& L) {
  Vector10 phi;
  phi[kMass] = m;
  phi.segment<3>(kCx) = c;
  phi.segment<3>(kBeta1) = beta;
  phi.segment<3>(kLx) = L;
  return phi;
}

// pi of the body phi describes, built by closed_form_bodies (independent construction).
Vector10 ReferencePi(const Vector10& phi) {
  Pose pose;
  pose.R_BC = AngleAxisRotation(phi.segment<3>(kBeta1));
  pose.p_BoCo_B = phi.segment<3>(kCx);
  return BodyFromSecondMoments(phi[kMass], phi.segment<3>(kLx), pose).vector();
}

Vector3 RandomDirection(Rng& rng) {
  // One draw per statement, in the order the x86-64 build drew them (see testing::Rng).
  const double z = rng.Normal();
  const double y = rng.Normal();
  const double x = rng.Normal();
  return Vector3(x, y, z).normalized();
}

// A random fully consistent body: mass, COM, uniformly random rotation, second moments.
InertialParams RandomBody(Rng& rng) {
  const Pose pose = rng.RandomPose<Pose>(1.0);
  const double m = rng.Uniform(0.1, 10.0);
  return BodyFromSecondMoments(m, m * rng.UniformVector<3>(1e-3, 0.5), pose);
}

// Product of the column norms: |det| / this is in [0, 1] (Hadamard's inequality), a scale-free
// measure of how singular a square matrix is.
double ColumnNormProduct(const Matrix10& J) {
  double p = 1.0;
  for (int k = 0; k < 10; ++k) p *= J.col(k).norm();
  return p;
}

double SingularValueRatio(const Matrix10& J) {
  const Eigen::JacobiSVD<Matrix10> svd(J);
  return svd.singularValues()[9] / svd.singularValues()[0];
}

// ---------------------------------------------------------------------------------------------
// The rotation exp / log and the derivative of exp.

TEST(EigenvalueRotation, ExpMatchesAngleAxis) {
  Rng rng(101);
  for (int n = 0; n < 2000; ++n) {
    const Vector3 direction = RandomDirection(rng);  // drawn before the angle, as on x86-64 (see testing::Rng)
    const Vector3 beta = rng.Uniform(0.0, 3.0 * kPi) * direction;
    EXPECT_LT(RelativeError(RotationFromExponentialCoordinates(beta), AngleAxisRotation(beta)), 1e-14)
        << beta.transpose();
  }
  for (double angle : {0.0, 1e-12, 1e-8, 1e-4, 1e-3 * (1.0 - 1e-12), 1e-3, 1e-3 * (1.0 + 1e-12), 1e-2, kPi}) {
    const Vector3 beta = angle * RandomDirection(rng);
    EXPECT_LT(RelativeError(RotationFromExponentialCoordinates(beta), AngleAxisRotation(beta)), 1e-15) << angle;
  }
}

TEST(EigenvalueRotation, DerivativeMatchesGallegoYezziAndCentralDifferences) {
  Rng rng(102);
  const Vector3 zero = Vector3::Zero();
  for (int n = 0; n < 1000; ++n) {
    const Vector3 direction = RandomDirection(rng);  // drawn before the angle, as on x86-64 (see testing::Rng)
    const Vector3 beta = rng.Uniform(0.05, 2.5 * kPi) * direction;
    std::array<Matrix3, 3> dR;
    RotationFromExponentialCoordinates(beta, &dR);
    for (int k = 0; k < 3; ++k) {
      EXPECT_LT(RelativeError(dR[k], GallegoYezziDerivative(beta, k)), 1e-12) << beta.transpose() << " k=" << k;
      const std::function<Eigen::Matrix<double, 9, 1>(const Eigen::Matrix<double, 1, 1>&)> f =
          [&](const Eigen::Matrix<double, 1, 1>& t) {
            const Matrix3 R = AngleAxisRotation(beta + t[0] * Vector3::Unit(k));
            return Eigen::Matrix<double, 9, 1>(Eigen::Map<const Eigen::Matrix<double, 9, 1>>(R.data()));
          };
      const Eigen::Matrix<double, 9, 1> fd = CentralDifference<9, 1>(f, Eigen::Matrix<double, 1, 1>::Zero());
      EXPECT_LT(RelativeError(Eigen::Map<const Eigen::Matrix<double, 9, 1>>(dR[k].data()), fd), 1e-8);
    }
  }
  // Hard points: 0 (dR/dbeta_k = S(e_k) exactly), tiny angles (second-order expansion
  // S(e_k) + (S(e_k) S(beta) + S(beta) S(e_k)) / 2, error O(|beta|^2)), the series/closed-form
  // switch, and angles at and near pi and 2 pi.
  std::array<Matrix3, 3> dR;
  RotationFromExponentialCoordinates(zero, &dR);
  for (int k = 0; k < 3; ++k) EXPECT_EQ(dR[k], Skew(Vector3::Unit(k)));
  for (double angle : {1e-12, 1e-8, 1e-6}) {
    const Vector3 beta = angle * RandomDirection(rng);
    RotationFromExponentialCoordinates(beta, &dR);
    for (int k = 0; k < 3; ++k) {
      const Matrix3 Se = Skew(Vector3::Unit(k));
      const Matrix3 expansion = Se + 0.5 * (Se * Skew(beta) + Skew(beta) * Se);
      EXPECT_LT(RelativeError(dR[k], expansion), 1e-15 + angle * angle) << angle;
    }
  }
  for (double angle : {1e-3 * (1.0 - 1e-9), 1e-3 * (1.0 + 1e-9), 1e-2, kPi - 1e-6, kPi, kPi + 1e-6, 2.0 * kPi - 1e-3}) {
    const Vector3 beta = angle * RandomDirection(rng);
    RotationFromExponentialCoordinates(beta, &dR);
    for (int k = 0; k < 3; ++k) {
      EXPECT_LT(RelativeError(dR[k], GallegoYezziDerivative(beta, k)), 1e-12) << angle << " k=" << k;
    }
  }
}

TEST(EigenvalueRotation, LogInvertsExp) {
  Rng rng(103);
  for (int n = 0; n < 5000; ++n) {
    const Vector3 direction = RandomDirection(rng);  // drawn before the angle, as on x86-64 (see testing::Rng)
    const Vector3 beta = rng.Uniform(0.0, kPi * (1.0 - 1e-9)) * direction;
    EXPECT_LT(RelativeError(ExponentialCoordinatesOfRotation(AngleAxisRotation(beta)), beta), 1e-12)
        << beta.transpose();
  }
  // Hard angles: 0, tiny, the pi/2 branch switch, and close to pi (where sin t -> 0).
  for (double angle : {0.0, 1e-300, 1e-12, 1e-6, kPi / 2.0 - 1e-12, kPi / 2.0, kPi / 2.0 + 1e-12, kPi - 1e-3,
                       kPi - 1e-6, kPi - 1e-9, kPi - 1e-12}) {
    for (int n = 0; n < 20; ++n) {
      const Vector3 beta = angle * RandomDirection(rng);
      EXPECT_LT(RelativeError(ExponentialCoordinatesOfRotation(AngleAxisRotation(beta)), beta), 1e-12) << angle;
    }
  }
  // At exactly pi either preimage is correct: check exp(log(R)) = R and |log R| = pi.
  for (int n = 0; n < 200; ++n) {
    const Vector3 axis = RandomDirection(rng);
    const Matrix3 R = 2.0 * axis * axis.transpose() - Matrix3::Identity();  // rotation by pi about axis
    const Vector3 beta = ExponentialCoordinatesOfRotation(R);
    EXPECT_NEAR(beta.norm(), kPi, 1e-14);
    EXPECT_LT(RelativeError(AngleAxisRotation(beta), R), 1e-14);
  }
  // Any rotation: |log R| <= pi and exp(log R) = R.
  for (int n = 0; n < 5000; ++n) {
    const Matrix3 R = rng.Rotation();
    const Vector3 beta = ExponentialCoordinatesOfRotation(R);
    EXPECT_LE(beta.norm(), kPi + 1e-15);
    EXPECT_LT(RelativeError(AngleAxisRotation(beta), R), 1e-14);
  }
}

// ---------------------------------------------------------------------------------------------
// pi(phi) and its Jacobian.

TEST(EigenvalueParameterization, ToPiMatchesBodyFromSecondMoments) {
  const EigenvalueParameterization param;
  EXPECT_EQ(param.name(), "eigenvalue");
  Rng rng(104);
  for (int n = 0; n < 2000; ++n) {
    // One draw per statement, in the order the x86-64 build drew them (see testing::Rng).
    const Vector3 L = rng.UniformVector<3>(1e-3, 2.0);
    const Vector3 beta = rng.UniformVector<3>(-4.0, 4.0);
    const Vector3 c = rng.UniformVector<3>(-2.0, 2.0);
    const Vector10 phi = Phi(rng.Uniform(0.01, 10.0), c, beta, L);
    const Vector10 pi = param.ToPi(phi);
    EXPECT_LT(RelativeError(pi, ReferencePi(phi)), 1e-13) << phi.transpose();
    EXPECT_TRUE(IsPhysicallyConsistent(InertialParams::FromVector(pi))) << phi.transpose();
  }
  // Negative mass or second moments: finite pi (not consistent), still the same formula.
  for (int n = 0; n < 500; ++n) {
    // One draw per statement, in the order the x86-64 build drew them (see testing::Rng).
    const Vector3 L = rng.UniformVector<3>(-2.0, 2.0);
    const Vector3 beta = rng.UniformVector<3>(-4.0, 4.0);
    const Vector3 c = rng.UniformVector<3>(-2.0, 2.0);
    const Vector10 phi = Phi(rng.Uniform(-5.0, 5.0), c, beta, L);
    const Vector10 pi = param.ToPi(phi);
    ASSERT_TRUE(pi.allFinite()) << phi.transpose();
    EXPECT_LT(RelativeError(pi, ReferencePi(phi)), 1e-13) << phi.transpose();
  }
  Vector10 negative_mass = Phi(-1.0, Vector3(0.1, 0.2, 0.3), Vector3(0.3, -0.2, 0.1), Vector3(0.1, 0.2, 0.3));
  EXPECT_FALSE(IsPhysicallyConsistent(InertialParams::FromVector(param.ToPi(negative_mass))));
  Vector10 negative_L = Phi(1.0, Vector3(0.1, 0.2, 0.3), Vector3(0.3, -0.2, 0.1), Vector3(-0.1, 0.2, 0.3));
  EXPECT_FALSE(IsPhysicallyConsistent(InertialParams::FromVector(param.ToPi(negative_L))));
}

TEST(EigenvalueParameterization, JacobianMatchesCentralDifferences) {
  const EigenvalueParameterization param;
  const std::function<Vector10(const Vector10&)> f = [&](const Vector10& x) { return param.ToPi(x); };
  Rng rng(105);
  std::vector<Vector10> points;
  for (int n = 0; n < 500; ++n) {
    // One draw per statement, in the order the x86-64 build drew them (see testing::Rng).
    const Vector3 L = rng.UniformVector<3>(-1.0, 2.0);
    const Vector3 beta = rng.UniformVector<3>(-4.0, 4.0);
    const Vector3 c = rng.UniformVector<3>(-2.0, 2.0);
    points.push_back(Phi(rng.Uniform(-3.0, 10.0), c, beta, L));
  }
  // Hard points for the rotation: beta = 0, tiny, at the series switch, near and at pi, near 2 pi.
  for (double angle : {0.0, 1e-8, 1e-3, kPi - 1e-6, kPi, 2.0 * kPi - 1e-2}) {
    points.push_back(Phi(2.0, Vector3(0.1, -0.3, 0.2), angle * RandomDirection(rng), Vector3(0.1, 0.2, 0.3)));
  }
  // A symmetric body (the Jacobian is singular there but still exact).
  points.push_back(Phi(2.0, Vector3(0.1, -0.3, 0.2), Vector3(0.4, 0.5, -0.6), Vector3(0.2, 0.2, 0.3)));
  for (const Vector10& phi : points) {
    Matrix10 J;
    const Vector10 pi = param.ToPi(phi, &J);
    EXPECT_EQ(pi, param.ToPi(phi));  // asking for J does not change pi
    EXPECT_LT(RelativeError(J, CentralDifference<10, 10>(f, phi)), 1e-6) << phi.transpose();
  }
}

// ---------------------------------------------------------------------------------------------
// The inverse.

TEST(EigenvalueParameterization, RoundTripPiPhiPi) {
  const EigenvalueParameterization param;
  Rng rng(106);
  std::vector<InertialParams> bodies;
  for (int n = 0; n < 5000; ++n) bodies.push_back(RandomBody(rng));
  // Hard bodies: rotations by pi (the log's hardest case), symmetric bodies (repeated L: the
  // eigenvectors are not unique), a sphere, and the identity pose.
  for (int n = 0; n < 50; ++n) {
    const Vector3 axis = RandomDirection(rng);
    Pose pose;
    pose.R_BC = 2.0 * axis * axis.transpose() - Matrix3::Identity();
    pose.p_BoCo_B = rng.UniformVector<3>(-1.0, 1.0);
    bodies.push_back(SolidBox(1.5, 0.1, 0.2, 0.3, pose));
    pose.R_BC = rng.Rotation();
    bodies.push_back(SolidCylinder(2.0, 0.1, 0.5, pose));
    bodies.push_back(SolidSphere(3.0, 0.2, pose));
  }
  bodies.push_back(SolidEllipsoid(1.0, 0.1, 0.2, 0.3));
  double worst = 0.0;
  for (const InertialParams& body : bodies) {
    const Vector10& pi = body.vector();
    Vector10 phi;
    ASSERT_TRUE(param.FromPi(pi, &phi)) << pi.transpose();
    const double err = RelativeError(param.ToPi(phi), pi);
    worst = std::max(worst, err);
    EXPECT_LT(err, 1e-10) << pi.transpose();
    // The preimage has the body's mass and COM, |beta| <= pi, ascending positive L.
    EXPECT_EQ(phi[kMass], body.mass());
    EXPECT_LT(RelativeError(phi.segment<3>(kCx), body.com()), 1e-14);
    EXPECT_LE(phi.segment<3>(kBeta1).norm(), kPi + 1e-12);
    EXPECT_GT(phi[kLx], 0.0);
    EXPECT_LE(phi[kLx], phi[kLy]);
    EXPECT_LE(phi[kLy], phi[kLz]);
  }
  RecordProperty("worst_relative_error", std::to_string(worst));
}

// The second moments found are those the body was built from (as a set, in ascending order).
TEST(EigenvalueParameterization, FromPiRecoversTheSecondMoments) {
  const EigenvalueParameterization param;
  Rng rng(107);
  for (int n = 0; n < 1000; ++n) {
    const double m = rng.Uniform(0.1, 10.0);
    Vector3 L = m * rng.UniformVector<3>(1e-3, 0.5);
    const Pose pose = rng.RandomPose<Pose>(1.0);
    Vector10 phi;
    ASSERT_TRUE(param.FromPi(BodyFromSecondMoments(m, L, pose).vector(), &phi));
    std::sort(L.data(), L.data() + 3);
    EXPECT_LT(RelativeError(phi.segment<3>(kLx), L), 1e-12) << L.transpose();
  }
}

TEST(EigenvalueParameterization, FromPiRefusesInconsistentBodiesAndLeavesPhiUntouched) {
  const EigenvalueParameterization param;
  const Vector10 sentinel = Vector10::Constant(42.0);
  Vector10 phi = sentinel;
  const std::vector<Vector10> refused = testing::InconsistentBodies(108);
  for (const Vector10& pi : refused) {
    EXPECT_FALSE(param.FromPi(pi, &phi)) << pi.transpose();
    EXPECT_EQ(phi, sentinel);
  }
}

// Consistent by construction iff m > 0 and L > 0; pi's numerical check agrees away from the
// boundary.
TEST(EigenvalueParameterization, YieldsConsistentBodyIffMassAndSecondMomentsArePositive) {
  const EigenvalueParameterization param;
  Rng rng(113);
  int yes = 0, no = 0;
  for (int n = 0; n < 4000; ++n) {
    // One draw per statement, in the order the x86-64 build drew them (see testing::Rng).
    const Vector3 L = rng.UniformVector<3>(-0.5, 1.0);
    const Vector3 beta = rng.UniformVector<3>(-4.0, 4.0);
    const Vector3 c = rng.UniformVector<3>(-1.0, 1.0);
    Vector10 phi = Phi(rng.Uniform(-1.0, 3.0), c, beta, L);
    // Keep away from the boundary m = 0, L = 0, where the numerical check is decided by rounding.
    for (int i : {kMass, kLx, kLy, kLz}) {
      if (std::abs(phi[i]) < 0.05) phi[i] = 0.05;
    }
    const bool positive = phi[kMass] > 0.0 && phi[kLx] > 0.0 && phi[kLy] > 0.0 && phi[kLz] > 0.0;
    EXPECT_EQ(param.YieldsConsistentBody(phi), positive) << phi.transpose();
    EXPECT_EQ(IsPhysicallyConsistent(InertialParams::FromVector(param.ToPi(phi))), positive) << phi.transpose();
    (positive ? yes : no) += 1;
  }
  EXPECT_GT(yes, 500);
  EXPECT_GT(no, 500);
  Vector10 phi = Phi(1.0, Vector3(0.1, 0.2, 0.3), Vector3(0.3, -0.2, 0.1), Vector3(0.1, 0.2, 0.3));
  EXPECT_TRUE(param.YieldsConsistentBody(phi));
  phi[kLy] = 0.0;  // a plate
  EXPECT_FALSE(param.YieldsConsistentBody(phi));
  phi[kLy] = 0.2;
  phi[kBeta2] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(param.YieldsConsistentBody(phi));
  phi[kBeta2] = 0.0;
  phi[kMass] = 1e300;
  phi[kCx] = 1e300;  // m |c|^2 overflows
  EXPECT_FALSE(param.YieldsConsistentBody(phi));
}

// ---------------------------------------------------------------------------------------------
// The symmetry-induced singularities of Section III-A.

TEST(EigenvalueSingularity, DeterminantHasTheClosedForm) {
  const EigenvalueParameterization param;
  Rng rng(109);
  for (int n = 0; n < 2000; ++n) {
    // One draw per statement, in the order the x86-64 build drew them (see testing::Rng).
    const Vector3 L = rng.UniformVector<3>(-1.0, 2.0);
    const Vector3 beta = rng.UniformVector<3>(-5.0, 5.0);
    const Vector3 c = rng.UniformVector<3>(-2.0, 2.0);
    const Vector10 phi = Phi(rng.Uniform(-3.0, 5.0), c, beta, L);
    Matrix10 J;
    param.ToPi(phi, &J);
    const double closed = EigenvalueJacobianDeterminant(phi);
    // |det - closed| relative to Hadamard's bound, the scale of det's rounding error.
    EXPECT_LT(std::abs(J.determinant() - closed) / ColumnNormProduct(J), 1e-12) << phi.transpose();
    if (std::abs(closed) > 1e-6 * ColumnNormProduct(J)) {
      EXPECT_NEAR(J.determinant() / closed, 1.0, 1e-8);
    }
  }
  // At beta = 0 the factor 2 (1 - cos t)/t^2 is 1.
  const Vector10 phi = Phi(2.0, Vector3(0.1, 0.2, 0.3), Vector3::Zero(), Vector3(0.1, 0.2, 0.4));
  EXPECT_NEAR(EigenvalueJacobianDeterminant(phi), -2.0 * 8.0 * (-0.1) * (-0.2) * (-0.3), 1e-15);
}

// Section III-A: det(J_pi_phi) vanishes whenever two second moments are equal, whatever m, c, beta.
TEST(EigenvalueSingularity, JacobianIsSingularWhenTwoSecondMomentsAreEqual) {
  const EigenvalueParameterization param;
  Rng rng(110);
  for (int n = 0; n < 1000; ++n) {
    const double m = rng.Uniform(0.1, 10.0);
    const Vector3 c = rng.UniformVector<3>(-1.0, 1.0);
    const Vector3 beta = rng.UniformVector<3>(-3.0, 3.0);
    // Well separated second moments: L = m (a, a + s, a + 2 s) shuffled.
    const double a = rng.Uniform(0.01, 0.3), s = rng.Uniform(0.05, 0.3);
    Vector3 L = m * Vector3(a, a + s, a + 2.0 * s);
    std::shuffle(L.data(), L.data() + 3, rng.engine());
    Matrix10 J;
    param.ToPi(Phi(m, c, beta, L), &J);
    EXPECT_GT(std::abs(J.determinant()) / ColumnNormProduct(J), 1e-6) << L.transpose();

    for (int pair = 0; pair < 3; ++pair) {
      const int i = pair, j = (pair + 1) % 3;
      Vector3 Leq = L;
      Leq[j] = Leq[i];
      Matrix10 Jeq;
      param.ToPi(Phi(m, c, beta, Leq), &Jeq);
      EXPECT_LT(std::abs(Jeq.determinant()) / ColumnNormProduct(Jeq), 1e-10) << Leq.transpose();
      // The null direction: rotating the body about its symmetry axis (the principal axis k other
      // than i, j), R -> R exp(eps S(e_k)) = exp(eps S(R e_k)) R, leaves pi unchanged. With
      // dR = S(J_l dbeta) R that is the dbeta with J_l(beta) dbeta = R e_k.
      const int k = 3 - i - j;
      const Matrix3 R = AngleAxisRotation(beta);
      Vector10 direction = Vector10::Zero();
      direction.segment<3>(kBeta1) = LeftJacobian(beta).colPivHouseholderQr().solve(R.col(k));
      EXPECT_LT((Jeq * direction).norm() / (Jeq.norm() * direction.norm()), 1e-13) << Leq.transpose();
      // Not a null direction for the distinct L.
      EXPECT_GT((J * direction).norm() / (J.norm() * direction.norm()), 1e-4) << L.transpose();
    }
  }
}

// det / ((Lx - Ly)(Ly - Lz)(Lx - Lz)) stays bounded and nonzero as Lx -> Ly: the differences are
// exactly the vanishing factors (each simple).
TEST(EigenvalueSingularity, DeterminantIsProportionalToSecondMomentDifferences) {
  const EigenvalueParameterization param;
  Rng rng(111);
  for (int n = 0; n < 50; ++n) {
    const double m = rng.Uniform(0.5, 5.0);
    const Vector3 c = rng.UniformVector<3>(-1.0, 1.0);
    const Vector3 beta = rng.UniformVector<3>(-2.0, 2.0);
    const double Ly = rng.Uniform(0.1, 0.5), Lz = rng.Uniform(0.6, 1.0);
    std::vector<double> ratios;
    for (double delta = 1e-1; delta > 1e-7; delta /= 10.0) {
      const double Lx = Ly + delta;
      Matrix10 J;
      param.ToPi(Phi(m, c, beta, Vector3(Lx, Ly, Lz)), &J);
      ratios.push_back(J.determinant() / ((Lx - Ly) * (Ly - Lz) * (Lx - Lz)));
    }
    // The ratio neither blows up nor vanishes as delta -> 0: it stays at -2 m^3 det J_l(beta), with
    // det J_l = 2 (1 - cos t) / t^2 (the header's derivation), for every delta.
    const double t = beta.norm();
    const double limit = -2.0 * m * m * m * 2.0 * (1.0 - std::cos(t)) / (t * t);
    for (double r : ratios) EXPECT_NEAR(r / limit, 1.0, 1e-6) << r;
    EXPECT_GT(std::abs(limit), 0.0);
  }
}

// The same symmetric body (a solid cylinder) is a regular point of the log-Cholesky map
// (Section IV-B) but a singular point of the eigenvalue map.
TEST(EigenvalueSingularity, LogCholeskyIsRegularWhereTheEigenvalueMapIsSingular) {
  const EigenvalueParameterization eigenvalue;
  const LogCholeskyParameterization log_cholesky;
  Rng rng(112);
  for (int n = 0; n < 100; ++n) {
    const double mass = rng.Uniform(0.5, 5.0), radius = rng.Uniform(0.05, 0.3), length = rng.Uniform(0.2, 1.0);
    const Vector3 beta = rng.UniformVector<3>(-2.0, 2.0);
    const Vector3 c = rng.UniformVector<3>(-0.5, 0.5);
    Pose pose;
    pose.R_BC = AngleAxisRotation(beta);
    pose.p_BoCo_B = c;
    const InertialParams cylinder = SolidCylinder(mass, radius, length, pose);

    // The eigenvalue parameters of this cylinder (axis along the third principal axis).
    const Vector3 L = mass * Vector3(radius * radius / 4.0, radius * radius / 4.0, length * length / 12.0);
    const Vector10 phi = Phi(mass, c, beta, L);
    Matrix10 J_eig;
    ASSERT_LT(RelativeError(eigenvalue.ToPi(phi, &J_eig), cylinder.vector()), 1e-13);

    Matrix10 J_lc;
    const Vector10 theta = log_cholesky.ThetaOf(cylinder);
    ASSERT_LT(RelativeError(PiFromLogCholesky(theta, &J_lc), cylinder.vector()), 1e-12);

    const double ratio_eig = SingularValueRatio(J_eig);
    const double ratio_lc = SingularValueRatio(J_lc);
    EXPECT_LT(ratio_eig, 1e-13) << "eigenvalue map at the cylinder";
    EXPECT_GT(ratio_lc, 1e-6) << "log-Cholesky map at the cylinder";
    EXPECT_NE(LogCholeskyJacobianDeterminant(theta), 0.0);
  }
}

}  // namespace
}  // namespace inertial
