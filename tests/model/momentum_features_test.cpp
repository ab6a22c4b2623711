#include "inertial/model/momentum_features.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "examples/bundled_robots.hpp"
#include "test_support.hpp"

namespace inertial {
namespace {

using testing::Rng;
using examples::Arm7;
using examples::BundledRobot;
using examples::Leg3;

// A smooth excitation: q_i(t) = a_i sin(w_i t + phi_i) + b_i, with its exact derivatives.
struct Sines {
  Eigen::VectorXd a, w, phi, b;
  Eigen::VectorXd q(double t) const { return (a.array() * (w.array() * t + phi.array()).sin()).matrix() + b; }
  Eigen::VectorXd qd(double t) const { return (a.array() * w.array() * (w.array() * t + phi.array()).cos()).matrix(); }
  Eigen::VectorXd qdd(double t) const {
    return (-a.array() * w.array().square() * (w.array() * t + phi.array()).sin()).matrix();
  }
};

Sines RandomSines(int n, Rng& rng) {
  Sines s{Eigen::VectorXd(n), Eigen::VectorXd(n), Eigen::VectorXd(n), Eigen::VectorXd(n)};
  for (int i = 0; i < n; ++i) {
    s.a[i] = rng.Uniform(0.3, 1.2);
    s.w[i] = rng.Uniform(0.5, 3.0);
    s.phi[i] = rng.Uniform(-3, 3);
    s.b[i] = rng.Uniform(-0.5, 0.5);
  }
  return s;
}

// d/dt [P w] + H w = tau (Lagrange), with d/dt taken along the trajectory by a central difference
// in time and tau by the model's recursive Newton-Euler at the exact (q, qd, qdd): an independent
// reference for P and H together. Every effect kind that moves with the joints, rotors and a
// payload included; random coefficients about the prior.
TEST(MomentumFeatures, TheirTimeDerivativeIsTheInverseDynamics) {
  struct Case {
    BundledRobot robot;
    std::string effects;
  };
  const std::vector<Case> cases = {
      {Leg3(), "viscous,coulomb,offset,armature@knee,spring@hip,rotor@hip:gear=6"},
      {Arm7(), "viscous,coulomb:scale=0.05,asymmetric@joint3:scale=0.05,sigmoid@joint5:steepness=40:shift=-0.03,"
               "payload@tool0:mass=2,rotor@joint2:gear=-50"},
  };
  Rng rng(5);
  for (const Case& c : cases) {
    SCOPED_TRACE(c.effects);
    const RobotDynamics model = c.robot.Dynamics(c.effects);
    const int n = model.num_dofs();
    const int f = model.num_features();
    Eigen::VectorXd x(model.num_parameters());
    for (int i = 0; i < x.size(); ++i) x[i] = rng.Uniform(-0.3, 0.3);
    const Eigen::VectorXd w = model.Coefficients(x);
    const Sines s = RandomSines(n, rng);
    MomentumFeatures momentum(model);
    Eigen::MatrixXd P(n, f), H(n, f), P_plus(n, f), P_minus(n, f), H_unused(n, f);
    const double dt = 1e-4;
    for (int k = 0; k < 20; ++k) {
      const double t = rng.Uniform(0.0, 10.0);
      momentum.Compute(model, s.q(t), s.qd(t), P, H);
      momentum.Compute(model, s.q(t + dt), s.qd(t + dt), P_plus, H_unused);
      momentum.Compute(model, s.q(t - dt), s.qd(t - dt), P_minus, H_unused);
      const Eigen::VectorXd from_momentum = (P_plus - P_minus) * w / (2 * dt) + H * w;
      const Eigen::VectorXd tau = model.InverseDynamics(x, s.q(t), s.qd(t), s.qdd(t));
      // The time difference's error (dt^2 / 6 times the third derivative of p, about 1e-8 N m
      // here) and the directional difference's (kDirectionalStep^2, relative) are far below this.
      EXPECT_LT((from_momentum - tau).cwiseAbs().maxCoeff(), 1e-6 * std::max(1.0, tau.cwiseAbs().maxCoeff()))
          << "t = " << t << "\nmomentum form: " << from_momentum.transpose() << "\nRNEA: " << tau.transpose();
      // p = M qd: P w against the inverse dynamics' part linear in qdd, at qdd := qd.
      const Eigen::VectorXd p = model.InverseDynamics(x, s.q(t), Eigen::VectorXd::Zero(n), s.qd(t)) -
                                model.InverseDynamics(x, s.q(t), Eigen::VectorXd::Zero(n), Eigen::VectorXd::Zero(n));
      EXPECT_LT((P * w - p).cwiseAbs().maxCoeff(), 1e-12 * std::max(1.0, p.cwiseAbs().maxCoeff()));
    }
  }
}

// At rest the momentum is zero and H is what holds the robot up: A(q, 0, 0).
TEST(MomentumFeatures, AtRestPIsZeroAndHIsTheStaticFeatures) {
  const RobotDynamics model = Leg3().Dynamics("viscous,offset,spring@knee");
  const int n = model.num_dofs();
  MomentumFeatures momentum(model);
  Eigen::MatrixXd P(n, model.num_features()), H(n, model.num_features()), A(n, model.num_features());
  const Eigen::VectorXd q = Eigen::Vector3d(0.2, -0.7, 1.3);
  momentum.Compute(model, q, Eigen::VectorXd::Zero(n), P, H);
  model.Features(q, Eigen::VectorXd::Zero(n), Eigen::VectorXd::Zero(n), A);
  EXPECT_EQ(P.cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ((H - A).cwiseAbs().maxCoeff(), 0.0);
}

}  // namespace
}  // namespace inertial
