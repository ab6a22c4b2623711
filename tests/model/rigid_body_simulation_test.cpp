#include "inertial/model/rigid_body_simulation.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "inertial/inertia/closed_form_bodies.hpp"
#include "model/sample_times.hpp"
#include "test_support.hpp"

namespace inertial {
namespace {

using testing::Rng;
using testing::Times;

// Torque-free axisymmetric body about its COM (I1 = I2 != I3): omega_z is constant and
// (omega_x, omega_y) rotates at Omega = (I3 - I1) / I1 omega_z (Euler's equations, closed form).
TEST(RigidBodySimulation, SymmetricTopMatchesClosedForm) {
  const InertialParams top = SolidCylinder(2.0, 0.3, 0.2);  // I3 = m r^2 / 2, I1 = m (3 r^2 + l^2) / 12
  const double I1 = top.rotational_inertia_about_origin()(0, 0), I3 = top.rotational_inertia_about_origin()(2, 2);
  Vector6 xi0;
  xi0 << 0.7, -0.4, 2.5, 0.0, 0.0, 0.0;
  const std::vector<double> t = Times(0.05, 10.0);
  const SimulationResult sim = SimulateRigidBody(top, xi0, [](double) { return Vector6::Zero(); }, t);
  ASSERT_TRUE(sim.ok);
  const double Omega = (I3 - I1) / I1 * xi0[2];
  for (std::size_t k = 0; k < t.size(); ++k) {
    // omega_dot_x = -Omega omega_y, omega_dot_y = Omega omega_x.
    const double c = std::cos(Omega * t[k]), s = std::sin(Omega * t[k]);
    const Vector3 expected(c * xi0[0] - s * xi0[1], s * xi0[0] + c * xi0[1], xi0[2]);
    EXPECT_LT((sim.twists[k].head<3>() - expected).norm(), 1e-8) << "t = " << t[k];
    EXPECT_LT(sim.twists[k].tail<3>().norm(), 1e-12);
  }
}

// With a wrench, dE/dt = xi . w (power); with none, the energy and the body-frame Casimirs |p_lin|
// and p_ang . p_lin of the momentum p = I xi are conserved.
TEST(RigidBodySimulation, EnergyAndMomentumBehaveAsPhysicsSays) {
  Rng rng(5);
  for (int trial = 0; trial < 20; ++trial) {
    const Pose pose = rng.RandomPose<Pose>(0.5);
    // One draw per statement, in the order the x86-64 build drew them (see testing::Rng).
    const Vector3 L = rng.UniformVector<3>(0.01, 1.0);
    const InertialParams body = BodyFromSecondMoments(rng.Uniform(0.1, 1.0), L, pose);
    const Vector6 xi0 = rng.UniformVector<6>(-1.0, 1.0);

    const std::vector<double> t = Times(1e-3, 3.0);
    const SimulationResult free = SimulateRigidBody(body, xi0, [](double) { return Vector6::Zero(); }, t);
    ASSERT_TRUE(free.ok);
    const Matrix6 M = body.spatial_inertia();
    const Vector6 p0 = M * xi0;
    for (const Vector6& xi : free.twists) {
      const Vector6 p = M * xi;
      EXPECT_NEAR(KineticEnergy(body, xi), KineticEnergy(body, xi0), 1e-8 * (1 + KineticEnergy(body, xi0)));
      EXPECT_NEAR(p.tail<3>().norm(), p0.tail<3>().norm(), 1e-8);
      EXPECT_NEAR(p.head<3>().dot(p.tail<3>()), p0.head<3>().dot(p0.tail<3>()), 1e-8);
    }

    auto wrench = [](double s) {
      Vector6 w;
      for (int k = 0; k < 6; ++k) w[k] = std::sin(s + k);
      return w;
    };
    const SimulationResult driven = SimulateRigidBody(body, xi0, wrench, t);
    ASSERT_TRUE(driven.ok);
    // Work by Simpson's rule on the 1 ms grid (3000 intervals, even).
    double work = 0.0;
    for (std::size_t k = 0; k < t.size(); ++k) {
      const double weight = (k == 0 || k + 1 == t.size()) ? 1.0 : (k % 2 == 1 ? 4.0 : 2.0);
      work += weight * driven.twists[k].dot(wrench(t[k]));
    }
    work *= 1e-3 / 3.0;
    const double dE = KineticEnergy(body, driven.twists.back()) - KineticEnergy(body, xi0);
    EXPECT_NEAR(dE, work, 1e-7 * (1.0 + std::abs(work)));
  }
}

}  // namespace
}  // namespace inertial
