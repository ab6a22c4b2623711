#include "inertial/inertia/inertial_params.hpp"

#include <gtest/gtest.h>

#include "inertial/inertia/closed_form_bodies.hpp"
#include "test_support.hpp"

namespace inertial {
namespace {

using testing::RelativeError;
using testing::Rng;

// A body made of point masses: every conversion has an independent reference by direct summation.
struct PointCloud {
  std::vector<double> masses;
  std::vector<Vector3> points;
  double mass() const {
    double m = 0;
    for (double mi : masses) m += mi;
    return m;
  }
  Vector3 first_moment() const {
    Vector3 h = Vector3::Zero();
    for (std::size_t i = 0; i < masses.size(); ++i) h += masses[i] * points[i];
    return h;
  }
  // Eq. (1): I = sum m (|x|^2 1 - x x^T).
  Matrix3 inertia() const {
    Matrix3 I = Matrix3::Zero();
    for (std::size_t i = 0; i < masses.size(); ++i) {
      I += masses[i] * (points[i].squaredNorm() * Matrix3::Identity() - points[i] * points[i].transpose());
    }
    return I;
  }
  // Eq. (6): J = sum m q q^T.
  Matrix4 pseudo_inertia() const {
    Matrix4 J = Matrix4::Zero();
    for (std::size_t i = 0; i < masses.size(); ++i) {
      Vector4 q;
      q << points[i], 1.0;
      J += masses[i] * q * q.transpose();
    }
    return J;
  }
};

PointCloud RandomCloud(Rng& rng, int n) {
  PointCloud c;
  for (int i = 0; i < n; ++i) {
    c.masses.push_back(rng.Uniform(0.1, 2.0));
    c.points.push_back(rng.UniformVector<3>(-1.0, 1.0) + Vector3(0.3, -0.2, 0.5));
  }
  return c;
}

TEST(InertialParams, ConversionsMatchDirectSummation) {
  Rng rng(1);
  for (int trial = 0; trial < 100; ++trial) {
    const PointCloud cloud = RandomCloud(rng, 20);
    const InertialParams body = InertialParams::FromMassFirstMomentInertia(cloud.mass(), cloud.first_moment(), cloud.inertia());
    EXPECT_NEAR(body.mass(), cloud.mass(), 1e-13);
    EXPECT_LT(RelativeError(body.com(), cloud.first_moment() / cloud.mass()), 1e-14);
    EXPECT_LT(RelativeError(body.rotational_inertia_about_origin(), cloud.inertia()), 1e-14);
    EXPECT_LT(RelativeError(body.pseudo_inertia(), cloud.pseudo_inertia()), 1e-13);
    // About the COM: direct summation over the shifted points.
    PointCloud centred = cloud;
    for (Vector3& p : centred.points) p -= body.com();
    EXPECT_LT(RelativeError(body.rotational_inertia_about_com(), centred.inertia()), 1e-13);
    // Spatial inertia (eq. 2) as the kinetic energy form: 0.5 xi^T M xi = sum 0.5 m |v + omega x p|^2.
    const Vector6 xi = rng.UniformVector<6>(-1.0, 1.0);
    double energy = 0.0;
    for (std::size_t i = 0; i < cloud.masses.size(); ++i) {
      const Vector3 v = xi.tail<3>() + xi.head<3>().cross(cloud.points[i]);
      energy += 0.5 * cloud.masses[i] * v.squaredNorm();
    }
    EXPECT_NEAR(0.5 * xi.dot(body.spatial_inertia() * xi), energy, 1e-12 * energy);
  }
}

TEST(InertialParams, RoundTripsThroughEveryRepresentation) {
  Rng rng(2);
  for (int trial = 0; trial < 1000; ++trial) {
    const Pose pose = rng.RandomPose<Pose>(1.0);
    // One draw per statement, in the order the x86-64 build drew them (see testing::Rng).
    const double z = rng.Uniform(0.1, 1.0);
    const double y = rng.Uniform(0.1, 1.0);
    const double x = rng.Uniform(0.1, 1.0);
    const InertialParams body = SolidBox(rng.Uniform(0.1, 5.0), x, y, z, pose);
    const Vector10& pi = body.vector();
    EXPECT_LT(RelativeError(InertialParams::FromPseudoInertia(body.pseudo_inertia()).vector(), pi), 1e-15);
    EXPECT_LT(RelativeError(InertialParams::FromSpatialInertia(body.spatial_inertia()).vector(), pi), 1e-15);
    EXPECT_LT(RelativeError(InertialParams::FromMassComInertia(body.mass(), body.com(), body.rotational_inertia_about_com()).vector(), pi),
              1e-14);
    // Sigma and I-bar are each other's trace transforms (Section IV).
    const Matrix3 Sigma = body.second_moments_about_origin();
    EXPECT_LT(RelativeError(Matrix3(Sigma.trace() * Matrix3::Identity() - Sigma), body.rotational_inertia_about_origin()), 1e-15);
  }
}

TEST(InertialParams, TransformMatchesTransformedPointCloud) {
  Rng rng(3);
  for (int trial = 0; trial < 100; ++trial) {
    const PointCloud cloud = RandomCloud(rng, 10);
    const InertialParams body = InertialParams::FromMassFirstMomentInertia(cloud.mass(), cloud.first_moment(), cloud.inertia());
    const Matrix3 R_AB = rng.Rotation();
    const Vector3 p_AoBo_A = rng.UniformVector<3>(-2.0, 2.0);
    PointCloud moved = cloud;
    for (Vector3& p : moved.points) p = R_AB * p + p_AoBo_A;
    const InertialParams expected = InertialParams::FromMassFirstMomentInertia(moved.mass(), moved.first_moment(), moved.inertia());
    const InertialParams actual = body.Transformed(R_AB, p_AoBo_A);
    EXPECT_LT(RelativeError(actual.vector(), expected.vector()), 1e-13);
    // And back.
    EXPECT_LT(RelativeError(actual.Transformed(R_AB.transpose(), -R_AB.transpose() * p_AoBo_A).vector(), body.vector()), 1e-13);
  }
}

TEST(InertialParams, OrderAndSignConventions) {
  // One point mass of 2 kg at (1, 2, 3): Ixy = -m x y = -4, Iyz = -12, Ixz = -6, Ixx = m (y^2 + z^2) = 26.
  const InertialParams p = InertialParams::FromMassComInertia(2.0, Vector3(1, 2, 3), Matrix3::Zero());
  Vector10 expected;
  expected << 2, 2, 4, 6, 26, 20, 10, -4, -12, -6;
  EXPECT_LT(RelativeError(p.vector(), expected), 1e-15);
  EXPECT_EQ(p.spatial_inertia()(0, 4), -6.0);  // S(h)(0,1) = -hz
}

// PseudoInertiaGradient is the adjoint of the linear map J -> pi: g . pi(J) = tr(G J) for random g
// and random symmetric J (not only pseudo-inertias), and G is symmetric.
TEST(InertialParams, PseudoInertiaGradientIsTheAdjointOfPiFromPseudoInertia) {
  Rng rng(11);
  for (int trial = 0; trial < 50; ++trial) {
    const Vector10 g = rng.UniformVector<10>(-3.0, 3.0);
    Matrix4 J;
    for (int i = 0; i < 4; ++i) {
      for (int j = i; j < 4; ++j) J(i, j) = J(j, i) = rng.Uniform(-2.0, 2.0);
    }
    const Matrix4 G = PseudoInertiaGradient(g);
    EXPECT_EQ((G - G.transpose()).norm(), 0.0);
    const double direct = g.dot(PiFromPseudoInertia(J));
    EXPECT_NEAR((G * J).trace(), direct, 1e-13 * (1.0 + std::abs(direct)));
  }
}

TEST(InertialParams, RejectsMalformedMatrices) {
  Matrix6 M = SolidSphere(1.0, 0.2).spatial_inertia();
  M(4, 4) += 0.1;  // lower-right block not m 1
  EXPECT_THROW(InertialParams::FromSpatialInertia(M), std::invalid_argument);
  M = SolidSphere(1.0, 0.2, Pose{Matrix3::Identity(), Vector3(0.1, 0, 0)}).spatial_inertia();
  M(0, 3) = 0.5;  // S(h) has zero diagonal
  M(3, 0) = 0.5;
  EXPECT_THROW(InertialParams::FromSpatialInertia(M), std::invalid_argument);
  Matrix4 J = Matrix4::Identity();
  J(0, 1) = 0.5;  // asymmetric
  try {
    InertialParams::FromPseudoInertia(J);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("not symmetric"), std::string::npos);
  }
  J = Matrix4::Identity();
  J(2, 2) = std::nan("");
  EXPECT_THROW(InertialParams::FromPseudoInertia(J), std::invalid_argument);
}

}  // namespace
}  // namespace inertial
