#include "inertial/model/kinematic_tree.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <tuple>

#include "inertial/inertia/closed_form_bodies.hpp"
#include "test_support.hpp"

namespace inertial {
namespace {

using testing::Rng;

// A random branched tree: 7 bodies, revolute and prismatic joints with random unit axes, one fixed
// joint, random origins and random consistent inertias.
KinematicTree RandomTree(Rng& rng) {
  KinematicTree tree;
  const int parents[7] = {-1, 0, 1, 1, 3, 0, 5};
  for (int i = 0; i < 7; ++i) {
    JointModel j;
    j.name = "j" + std::to_string(i);
    j.type = i == 4 ? JointType::kFixed : (i == 2 || i == 6 ? JointType::kPrismatic : JointType::kRevolute);
    j.R_parent_joint = rng.Rotation();
    j.p_parent_joint = rng.UniformVector<3>(-0.4, 0.4);
    j.axis = rng.UniformVector<3>(-1, 1).normalized();
    // One draw per statement, in the order the x86-64 build drew them (see testing::Rng).
    const Pose pose{rng.Rotation(), rng.UniformVector<3>(-0.2, 0.2)};
    const Vector3 L = rng.UniformVector<3>(0.001, 0.05);
    const double mass = rng.Uniform(0.2, 3.0);
    const InertialParams body = BodyFromSecondMoments(mass, L, pose);
    tree.AddBody("b" + std::to_string(i), parents[i], j, body);
  }
  // Two geared rotors: one on the base driving body 0's joint, one on body 1 driving body 3's joint.
  for (const auto& [parent, driven, ratio] : {std::tuple{-1, 0, -9.0}, std::tuple{1, 3, 6.5}}) {
    JointModel j;
    j.name = "rotor_of_b" + std::to_string(driven);
    j.R_parent_joint = rng.Rotation();
    j.p_parent_joint = rng.UniformVector<3>(-0.1, 0.1);
    j.axis = rng.UniformVector<3>(-1, 1).normalized();
    // One draw per statement, in the order the x86-64 build drew them (see testing::Rng).
    const Pose pose{rng.Rotation(), rng.UniformVector<3>(-0.01, 0.01)};
    const Vector3 L = rng.UniformVector<3>(1e-5, 1e-3);
    const double mass = rng.Uniform(0.1, 0.5);
    const InertialParams rotor = BodyFromSecondMoments(mass, L, pose);
    tree.AddRotor(j.name, parent, j, rotor, tree.dof_index(driven), ratio);
  }
  return tree;
}

// tau = Y(q, qd, qdd) pi_all reproduces the recursive Newton-Euler torques exactly.
TEST(KinematicTree, RegressorTimesParametersEqualsInverseDynamics) {
  Rng rng(1);
  for (int trial = 0; trial < 100; ++trial) {
    const KinematicTree tree = RandomTree(rng);
    ASSERT_EQ(tree.num_dofs(), 6);
    const Eigen::VectorXd q = Eigen::VectorXd::NullaryExpr(6, [&] { return rng.Uniform(-3, 3); });
    const Eigen::VectorXd qd = Eigen::VectorXd::NullaryExpr(6, [&] { return rng.Uniform(-3, 3); });
    const Eigen::VectorXd qdd = Eigen::VectorXd::NullaryExpr(6, [&] { return rng.Uniform(-3, 3); });
    const Vector3 g = rng.UniformVector<3>(-10, 10);
    const Eigen::VectorXd tau = tree.InverseDynamics(q, qd, qdd, g);
    const Eigen::MatrixXd Y = tree.JointTorqueRegressor(q, qd, qdd, g);
    const Eigen::VectorXd tau_Y = Y * tree.StackedParameters();
    EXPECT_LT((tau - tau_Y).cwiseAbs().maxCoeff(), 1e-11 * (1.0 + tau.cwiseAbs().maxCoeff()));
    // Newton-Euler with given parameters, consistent or not (the map is linear in pi).
    const Eigen::VectorXd pi = Eigen::VectorXd::NullaryExpr(Y.cols(), [&] { return rng.Uniform(-1, 1); });
    const Eigen::VectorXd tau_pi = tree.InverseDynamics(pi, q, qd, qdd, g), Y_pi = Y * pi;
    EXPECT_LT((tau_pi - Y_pi).cwiseAbs().maxCoeff(), 1e-11 * (1.0 + Y_pi.cwiseAbs().maxCoeff()));
  }
}

// Independent reference: Lagrange's equations, tau = d/dt dL/dqd - dL/dq with L = T - V,
// T = sum 0.5 v_i^T M_i v_i and V = -sum m_i g . c_i, all by central differences.
TEST(KinematicTree, InverseDynamicsSatisfiesLagrangesEquations) {
  Rng rng(2);
  for (int trial = 0; trial < 10; ++trial) {
    const KinematicTree tree = RandomTree(rng);
    const int n = tree.num_dofs();
    const Vector3 g(0.3, -1.2, -9.81);
    auto lagrangian = [&](const Eigen::VectorXd& q, const Eigen::VectorXd& qd) {
      const std::vector<Vector6> v = tree.BodyVelocities(q, qd);
      const std::vector<SpatialTransform> pose = tree.BodyPoses(q);
      double L = 0.0;
      for (int i = 0; i < tree.num_bodies(); ++i) {
        const InertialParams& I = tree.inertia(i);
        L += 0.5 * v[i].dot(I.spatial_inertia() * v[i]);
        L += I.mass() * g.dot(pose[i].p_AB + pose[i].R_AB * I.com());
      }
      return L;
    };
    const Eigen::VectorXd q = Eigen::VectorXd::NullaryExpr(n, [&] { return rng.Uniform(-2, 2); });
    const Eigen::VectorXd qd = Eigen::VectorXd::NullaryExpr(n, [&] { return rng.Uniform(-2, 2); });
    const Eigen::VectorXd qdd = Eigen::VectorXd::NullaryExpr(n, [&] { return rng.Uniform(-2, 2); });
    const double h = 1e-5, dt = 1e-4;
    auto dL_dqd = [&](const Eigen::VectorXd& qq, const Eigen::VectorXd& qqd) {
      Eigen::VectorXd p(n);
      for (int k = 0; k < n; ++k) {
        Eigen::VectorXd up = qqd, dn = qqd;
        up[k] += h;
        dn[k] -= h;
        p[k] = (lagrangian(qq, up) - lagrangian(qq, dn)) / (2 * h);
      }
      return p;
    };
    // d/dt along q(t) = q + qd t + qdd t^2 / 2.
    const Eigen::VectorXd ddt = (dL_dqd(q + qd * dt + 0.5 * qdd * dt * dt, qd + qdd * dt) -
                                 dL_dqd(q - qd * dt + 0.5 * qdd * dt * dt, qd - qdd * dt)) /
                                (2 * dt);
    Eigen::VectorXd dL_dq(n);
    for (int k = 0; k < n; ++k) {
      Eigen::VectorXd up = q, dn = q;
      up[k] += h;
      dn[k] -= h;
      dL_dq[k] = (lagrangian(up, qd) - lagrangian(dn, qd)) / (2 * h);
    }
    const Eigen::VectorXd expected = ddt - dL_dq;
    const Eigen::VectorXd tau = tree.InverseDynamics(q, qd, qdd, g);
    EXPECT_LT((tau - expected).cwiseAbs().maxCoeff(), 1e-4 * (1.0 + expected.cwiseAbs().maxCoeff()))
        << tau.transpose() << "\n" << expected.transpose();
  }
}

// A pendulum: a sphere of mass m, radius r at distance l along x, revolute about z, gravity -y:
// tau = (2/5 m r^2 + m l^2) qdd + m g l cos q.
TEST(KinematicTree, PendulumClosedForm) {
  const double m = 1.3, r = 0.05, l = 0.7, g = 9.81;
  KinematicTree tree;
  JointModel j;
  j.name = "pivot";
  tree.AddBody("bob", -1, j, SolidSphere(m, r, Pose{Matrix3::Identity(), Vector3(l, 0, 0)}));
  for (double q : {-1.0, 0.0, 0.4, 2.5}) {
    for (double qdd : {-2.0, 0.0, 3.0}) {
      Eigen::VectorXd Q(1), Qd(1), Qdd(1);
      Q << q;
      Qd << 1.7;  // no effect on a single revolute joint's torque about a principal axis
      Qdd << qdd;
      const double expected = (0.4 * m * r * r + m * l * l) * qdd + m * g * l * std::cos(q);
      EXPECT_NEAR(tree.InverseDynamics(Q, Qd, Qdd, Vector3(0, -g, 0))[0], expected, 1e-12);
    }
  }
}

// A geared rotor on the base driving a pendulum: the rotor's axial inertia Ir appears reflected as
// N^2 Ir qdd on the joint; a rotor spinning about its axis of symmetry adds nothing else.
TEST(KinematicTree, GearedRotorReflectsInertiaByRatioSquared) {
  const double m = 1.3, r = 0.05, l = 0.7, g = 9.81, N = 9.0;
  KinematicTree tree;
  JointModel j;
  j.name = "pivot";
  tree.AddBody("bob", -1, j, SolidSphere(m, r, Pose{Matrix3::Identity(), Vector3(l, 0, 0)}));
  const InertialParams rotor = SolidCylinder(0.2, 0.03, 0.02);  // axis z, at the origin
  const double Ir = 0.5 * 0.2 * 0.03 * 0.03;
  j.name = "rotor";
  tree.AddRotor("rotor", -1, j, rotor, 0, N);
  EXPECT_EQ(tree.num_dofs(), 1);
  Eigen::VectorXd Q(1), Qd(1), Qdd(1);
  Q << 0.4;
  Qd << 1.7;
  Qdd << -2.3;
  const double expected = (0.4 * m * r * r + m * l * l + N * N * Ir) * Qdd[0] + m * g * l * std::cos(Q[0]);
  EXPECT_NEAR(tree.InverseDynamics(Q, Qd, Qdd, Vector3(0, -g, 0))[0], expected, 1e-12);
  EXPECT_THROW(tree.AddRotor("r2", -1, j, rotor, 1, N), std::invalid_argument);    // no DOF 1
  EXPECT_THROW(tree.AddRotor("r2", -1, j, rotor, 0, 0.0), std::invalid_argument);  // zero ratio
}

TEST(KinematicTree, RejectsBadInput) {
  KinematicTree tree;
  JointModel j;
  j.axis = Vector3(1, 1, 0);
  EXPECT_THROW(tree.AddBody("a", -1, j, SolidSphere(1, 0.1)), std::invalid_argument);  // axis not unit
  j.axis = Vector3::UnitZ();
  EXPECT_THROW(tree.AddBody("a", 3, j, SolidSphere(1, 0.1)), std::invalid_argument);  // no such parent
  tree.AddBody("a", -1, j, SolidSphere(1, 0.1));
  const Eigen::VectorXd two = Eigen::VectorXd::Zero(2);
  EXPECT_THROW(tree.InverseDynamics(two, two, two), std::invalid_argument);
  const Eigen::VectorXd one = Eigen::VectorXd::Zero(1);
  EXPECT_THROW(tree.InverseDynamics(Eigen::VectorXd::Zero(9), one, one, one, Vector3::Zero()), std::invalid_argument);
}

}  // namespace
}  // namespace inertial
