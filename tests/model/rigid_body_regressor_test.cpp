#include "inertial/model/rigid_body_regressor.hpp"

#include <gtest/gtest.h>

#include "inertial/inertia/closed_form_bodies.hpp"
#include "inertial/model/spatial_algebra.hpp"
#include "test_support.hpp"

namespace inertial {
namespace {

using testing::RelativeError;
using testing::Rng;

InertialParams RandomBody(Rng& rng) {
  const Pose pose = rng.RandomPose<Pose>(0.5);
  // One draw per statement, in the order the x86-64 build drew them (see testing::Rng).
  const Vector3 L = rng.UniformVector<3>(0.01, 1.0);
  return BodyFromSecondMoments(rng.Uniform(0.1, 3.0), L, pose);
}

// Independent reference 1: eq. (12) with the 6x6 matrices, I xi_dot + xi x* I xi - [h x g; m g].
TEST(RigidBodyRegressor, MatchesSpatialMatrixForm) {
  Rng rng(1);
  for (int trial = 0; trial < 1000; ++trial) {
    const InertialParams body = RandomBody(rng);
    const Vector6 xi = rng.UniformVector<6>(-3.0, 3.0);
    const Vector6 xi_dot = rng.UniformVector<6>(-3.0, 3.0);
    const Vector3 g = rng.UniformVector<3>(-10.0, 10.0);
    const Matrix6 M = body.spatial_inertia();
    Vector6 w_gravity;
    w_gravity << body.first_moment().cross(g), body.mass() * g;
    const Vector6 expected = M * xi_dot + ForceCross(xi) * M * xi - w_gravity;
    EXPECT_LT(RelativeError(RigidBodyRegressor(xi, xi_dot, g) * body.vector(), expected), 1e-13);
  }
}

// Independent reference 2: a cloud of particles. Each particle at p_i (body frame) has inertial
// acceleration a_i = (v_dot + omega x v) + alpha x p_i + omega x (omega x p_i) in body coordinates;
// the wrench about the origin is sum [p_i x m_i (a_i - g); m_i (a_i - g)].
TEST(RigidBodyRegressor, MatchesParticleNewtonEuler) {
  Rng rng(2);
  for (int trial = 0; trial < 200; ++trial) {
    std::vector<double> m;
    std::vector<Vector3> p;
    InertialParams body;
    for (int i = 0; i < 8; ++i) {
      m.push_back(rng.Uniform(0.1, 1.0));
      p.push_back(rng.UniformVector<3>(-1.0, 1.0));
      body = body + InertialParams::FromMassComInertia(m.back(), p.back(), Matrix3::Zero());
    }
    const Vector6 xi = rng.UniformVector<6>(-2.0, 2.0);
    const Vector6 xi_dot = rng.UniformVector<6>(-2.0, 2.0);
    const Vector3 g = rng.UniformVector<3>(-10.0, 10.0);
    const Vector3 omega = xi.head<3>(), v = xi.tail<3>(), alpha = xi_dot.head<3>(), v_dot = xi_dot.tail<3>();
    Vector6 expected = Vector6::Zero();
    for (std::size_t i = 0; i < m.size(); ++i) {
      const Vector3 a = v_dot + omega.cross(v) + alpha.cross(p[i]) + omega.cross(omega.cross(p[i]));
      const Vector3 f = m[i] * (a - g);
      expected.head<3>() += p[i].cross(f);
      expected.tail<3>() += f;
    }
    EXPECT_LT(RelativeError(RigidBodyRegressor(xi, xi_dot, g) * body.vector(), expected), 1e-13);
  }
}

TEST(RigidBodyRegressor, InertiaTimesVectorMapIsExact) {
  Rng rng(3);
  const InertialParams body = RandomBody(rng);
  const Vector3 x = rng.UniformVector<3>(-1.0, 1.0);
  EXPECT_LT(RelativeError(InertiaTimesVectorMap(x) * body.vector().tail<6>(), body.rotational_inertia_about_origin() * x), 1e-15);
}

}  // namespace
}  // namespace inertial
