#include "inertial/model/closed_loop_rate.hpp"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <cmath>
#include <complex>
#include <limits>
#include <stdexcept>
#include <string>

#include "inertial/inertia/closed_form_bodies.hpp"
#include "inertial/model/kinematic_tree.hpp"
#include "test_support.hpp"

namespace inertial {
namespace {

using testing::RelativeError;
using testing::Rng;

constexpr double kInf = std::numeric_limits<double>::infinity();

Eigen::LLT<Eigen::MatrixXd> Factor(const Eigen::MatrixXd& M) { return Eigen::LLT<Eigen::MatrixXd>(M); }

// One joint, id = I qdd + b qd + bc tanh(qd / vs) + k q + c, under PD feedback (kp, kd): the closed
// loop at qd = 0 is the 2 x 2 system [[0, 1], [-(kp + k) / I, -(kd + b + bc / vs) / I]], whose
// eigenvalues are the roots of I s^2 + (kd + b + bc / vs) s + (kp + k) = 0.
double ClosedFormRate(double I, double damping, double stiffness) {
  const std::complex<double> d = std::sqrt(std::complex<double>(damping * damping - 4 * I * stiffness));
  return std::max(std::abs((-damping + d) / (2 * I)), std::abs((-damping - d) / (2 * I)));
}

TEST(ClosedLoopRate, SingleJointAgainstTheRootsOfItsCharacteristicPolynomial) {
  struct Case {
    double I, b, bc, vs, k, kp, kd;
  };
  // Underdamped (|s| = sqrt((kp + k) / I)), overdamped by the gains, and at a Coulomb friction's
  // velocity reversal (slope bc / vs = 100 bc: the fast real mode).
  for (const Case& c : {Case{0.02, 0.1, 0.0, 0.01, 0.5, 400.0, 2.0}, Case{0.02, 0.1, 0.0, 0.01, 0.0, 40.0, 40.0},
                        Case{0.002, 0.1, 0.1, 0.01, 0.0, 2.0, 0.09}, Case{3.0, 0.0, 0.8, 0.05, 2.0, 1e4, 100.0}}) {
    const JointDynamicsFn plant = [c](const Eigen::VectorXd& q, const Eigen::VectorXd& qd, const Eigen::VectorXd& qdd) {
      return Eigen::VectorXd::Constant(
          1, c.I * qdd[0] + c.b * qd[0] + c.bc * std::tanh(qd[0] / c.vs) + c.k * q[0] + 0.7);
    };
    const Eigen::VectorXd q = Eigen::VectorXd::Constant(1, 0.4), qd = Eigen::VectorXd::Zero(1);
    const Eigen::VectorXd qdd = Eigen::VectorXd::Constant(1, -1.3);
    const Eigen::MatrixXd J = ClosedLoopJacobian(plant, Factor(Eigen::MatrixXd::Constant(1, 1, c.I)), q, qd, qdd,
                                                 PdCommandSlopes(Eigen::VectorXd::Constant(1, c.kp),
                                                                 Eigen::VectorXd::Constant(1, c.kd)));
    Eigen::Matrix2d expected;
    expected << 0, 1, -(c.kp + c.k) / c.I, -(c.kd + c.b + c.bc / c.vs) / c.I;
    EXPECT_LT(RelativeError(J, expected), 1e-6) << J;
    const double rate = ClosedFormRate(c.I, c.kd + c.b + c.bc / c.vs, c.kp + c.k);
    EXPECT_NEAR(SpectralRadius(J), rate, 1e-6 * rate);
  }
}

// Computed torque cancels a joint's friction in the closed loop (J(C) is the PD loop alone, rate
// sqrt(kp) for kd^2 < 4 kp) but not within a step, where the command is held: the held-command
// plant keeps the friction's real mode -(b + bc / vs) / I, and the step rate is the larger.
TEST(ClosedLoopRate, StepRateIsTheLargerOfTheHeldPlantAndTheClosedLoop) {
  const double I = 0.002, b = 0.1, bc = 0.1, vs = 0.01, kp = 987.0, kd = 44.0;
  const JointDynamicsFn plant = [=](const Eigen::VectorXd&, const Eigen::VectorXd& qd, const Eigen::VectorXd& qdd) {
    return Eigen::VectorXd::Constant(1, I * qdd[0] + b * qd[0] + bc * std::tanh(qd[0] / vs));
  };
  const JointControllerFn computed_torque = [&](double, const Eigen::VectorXd& q, const Eigen::VectorXd& qd) {
    return plant(q, qd, -kp * q - kd * qd);
  };
  const Eigen::VectorXd q = Eigen::VectorXd::Constant(1, 0.01), qd = Eigen::VectorXd::Zero(1);
  const Eigen::VectorXd tau = computed_torque(0.0, q, qd);
  const Eigen::LLT<Eigen::MatrixXd> mass = Factor(Eigen::MatrixXd::Constant(1, 1, I));
  const Eigen::VectorXd qdd = Eigen::VectorXd::Constant(1, (tau[0] - plant(q, qd, Eigen::VectorXd::Zero(1))[0]) / I);
  const PlantSlopes p = DifferencedPlantSlopes(plant, q, qd, qdd);
  EXPECT_NEAR(p.dq(0, 0), 0.0, 1e-12);
  EXPECT_NEAR(p.dqd(0, 0), b + bc / vs, 1e-6);
  const CommandSlopes c = DifferencedCommandSlopes(computed_torque, 0.0, q, qd, tau);
  const Eigen::MatrixXd closed = LoopJacobian(mass, p, c);
  EXPECT_LT(RelativeError(closed, (Eigen::Matrix2d() << 0, 1, -kp, -kd).finished()), 1e-6) << closed;
  const double friction = (b + bc / vs) / I;  // 5050 1/s
  EXPECT_NEAR(SpectralRadius(closed), std::sqrt(kp), 1e-5 * std::sqrt(kp));
  EXPECT_NEAR(StepRate(mass, p, c), friction, 1e-6 * friction);
  // Without friction the closed loop is the faster.
  const PlantSlopes inertia_only{Eigen::MatrixXd::Zero(1, 1), Eigen::MatrixXd::Zero(1, 1)};
  const CommandSlopes pd{Eigen::MatrixXd::Constant(1, 1, -I * kp), Eigen::MatrixXd::Constant(1, 1, -I * kd)};
  EXPECT_NEAR(StepRate(mass, inertia_only, pd), std::sqrt(kp), 1e-9 * std::sqrt(kp));
  EXPECT_THROW(LoopJacobian(mass, p, CommandSlopes{Eigen::MatrixXd::Zero(2, 2), Eigen::MatrixXd::Zero(2, 2)}),
               std::invalid_argument);
}

// A random serial chain of n revolute joints with random axes, origins and bodies.
KinematicTree RandomChain(Rng& rng, int n) {
  KinematicTree tree;
  for (int i = 0; i < n; ++i) {
    JointModel j;
    j.name = "j" + std::to_string(i);
    j.R_parent_joint = rng.Rotation();
    j.p_parent_joint = rng.UniformVector<3>(-0.3, 0.3);
    j.axis = rng.UniformVector<3>(-1, 1).normalized();
    // One draw per statement, in the order the x86-64 build drew them (see testing::Rng).
    const Pose pose{rng.Rotation(), rng.UniformVector<3>(-0.2, 0.2)};
    const Vector3 L = rng.UniformVector<3>(0.001, 0.03);
    const double mass = rng.Uniform(0.2, 2.0);
    const InertialParams body = BodyFromSecondMoments(mass, L, pose);
    tree.AddBody("b" + std::to_string(i), i - 1, j, body);
  }
  return tree;
}

// The full closed loop x' = F(x) = (qd, f(q, qd)), f by Cholesky of the mass matrix built here from
// the plant's columns, differentiated by central differences: the reference for the Jacobian.
Eigen::MatrixXd CentralDifferenceJacobian(const JointDynamicsFn& plant, const JointControllerFn& controller, double t,
                                          const Eigen::VectorXd& x0) {
  const Eigen::Index n = x0.size() / 2;
  auto F = [&](const Eigen::VectorXd& x) {
    const Eigen::VectorXd q = x.head(n), qd = x.tail(n);
    const Eigen::VectorXd zero = Eigen::VectorXd::Zero(n);
    const Eigen::VectorXd h = plant(q, qd, zero);
    Eigen::MatrixXd M(n, n);
    for (Eigen::Index k = 0; k < n; ++k) M.col(k) = plant(q, qd, Eigen::VectorXd::Unit(n, k)) - h;
    Eigen::VectorXd out(2 * n);
    out << qd, Eigen::MatrixXd(M).ldlt().solve(controller(t, q, qd) - h);
    return out;
  };
  Eigen::MatrixXd J(2 * n, 2 * n);
  const double step = 1e-6;
  for (Eigen::Index k = 0; k < 2 * n; ++k) {
    Eigen::VectorXd xp = x0, xm = x0;
    xp[k] += step;
    xm[k] -= step;
    J.col(k) = (F(xp) - F(xm)) / (2 * step);
  }
  return J;
}

TEST(ClosedLoopRate, JacobianOfATreeMatchesCentralDifferencesOfTheClosedLoop) {
  Rng rng(17);
  for (int trial = 0; trial < 5; ++trial) {
    const int n = 5;
    const KinematicTree tree = RandomChain(rng, n);
    const Vector3 g(0, 0, -9.81);
    Eigen::VectorXd b(n), bc(n);
    for (int k = 0; k < n; ++k) {
      b[k] = rng.Uniform(0, 0.5);
      bc[k] = rng.Uniform(0, 0.5);
    }
    // Coulomb friction smoothed at 0.5 rad/s here, so central differences of step 1e-6 resolve it.
    const JointDynamicsFn plant = [&](const Eigen::VectorXd& q, const Eigen::VectorXd& qd, const Eigen::VectorXd& qdd) {
      return (tree.InverseDynamics(q, qd, qdd, g) + b.cwiseProduct(qd) +
              bc.cwiseProduct((qd / 0.5).array().tanh().matrix()))
          .eval();
    };
    Eigen::VectorXd kp(n), kd(n), q(n), qd(n);
    for (int k = 0; k < n; ++k) {
      kp[k] = rng.Uniform(10, 100);
      kd[k] = rng.Uniform(1, 10);
      q[k] = rng.Uniform(-2, 2);
      qd[k] = rng.Uniform(-1, 1);
    }
    const Eigen::VectorXd q_ref = Eigen::VectorXd::Constant(n, 0.3), qd_ref = Eigen::VectorXd::Constant(n, -0.2);
    const JointControllerFn pd = [&](double t, const Eigen::VectorXd& qq, const Eigen::VectorXd& vv) {
      return (Eigen::VectorXd::Constant(n, std::sin(t)) + kp.cwiseProduct(q_ref - qq) + kd.cwiseProduct(qd_ref - vv))
          .eval();
    };
    const double t = 0.7;
    const Eigen::VectorXd tau = pd(t, q, qd);
    const Eigen::VectorXd zero = Eigen::VectorXd::Zero(n);
    Eigen::MatrixXd M(n, n);
    for (int k = 0; k < n; ++k) M.col(k) = plant(q, qd, Eigen::VectorXd::Unit(n, k)) - plant(q, qd, zero);
    const Eigen::LLT<Eigen::MatrixXd> mass(0.5 * (M + M.transpose()));
    const Eigen::VectorXd qdd = mass.solve(tau - plant(q, qd, zero));
    Eigen::VectorXd x(2 * n);
    x << q, qd;
    const Eigen::MatrixXd expected = CentralDifferenceJacobian(plant, pd, t, x);
    // With the PD slopes known, and with the controller differenced: the same Jacobian.
    const Eigen::MatrixXd J_pd = ClosedLoopJacobian(plant, mass, q, qd, qdd, PdCommandSlopes(kp, kd));
    const Eigen::MatrixXd J_any =
        ClosedLoopJacobian(plant, mass, q, qd, qdd, DifferencedCommandSlopes(pd, t, q, qd, tau));
    EXPECT_LT(RelativeError(J_pd, expected), 1e-5) << "trial " << trial;
    EXPECT_LT(RelativeError(J_any, expected), 1e-5) << "trial " << trial;
    const double rho = SpectralRadius(expected);
    EXPECT_NEAR(SpectralRadius(J_pd), rho, 1e-5 * rho);
  }
}

TEST(ClosedLoopRate, DifferencedSlopesOfALinearController) {
  const Eigen::Matrix2d A = (Eigen::Matrix2d() << -3, 1, 0.5, -7).finished();
  const Eigen::Matrix2d B = (Eigen::Matrix2d() << -0.2, 0, 0.1, -0.4).finished();
  const JointControllerFn linear = [&](double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd) {
    return (A * q + B * qd + Eigen::Vector2d::Constant(t)).eval();
  };
  const Eigen::Vector2d q(1e3, -0.5), qd(0.2, 40);
  const Eigen::VectorXd tau = linear(2.0, q, qd);
  const CommandSlopes s = DifferencedCommandSlopes(linear, 2.0, q, qd, tau);
  // Forward differences are exact on a linear function but for the rounding of tau: a few units in
  // its last place over the step sqrt(eps) max(1, |x_k|) (here |tau| ~ 3000 against slopes of 0.1).
  const double eps = std::numeric_limits<double>::epsilon(), ulps = 8 * eps * tau.cwiseAbs().maxCoeff();
  for (int k = 0; k < 2; ++k) {
    const double step_q = std::sqrt(eps) * std::max(1.0, std::abs(q[k]));
    const double step_qd = std::sqrt(eps) * std::max(1.0, std::abs(qd[k]));
    EXPECT_LT((s.dq.col(k) - A.col(k)).cwiseAbs().maxCoeff(), ulps / step_q);
    EXPECT_LT((s.dqd.col(k) - B.col(k)).cwiseAbs().maxCoeff(), ulps / step_qd);
  }
  const CommandSlopes pd = PdCommandSlopes(Eigen::Vector2d(4, 5), Eigen::Vector2d(0.5, 0.25));
  EXPECT_EQ(pd.dq, (Eigen::Matrix2d() << -4, 0, 0, -5).finished());
  EXPECT_EQ(pd.dqd, (Eigen::Matrix2d() << -0.5, 0, 0, -0.25).finished());
  EXPECT_THROW(PdCommandSlopes(Eigen::Vector2d(1, 2), Eigen::Vector3d(1, 2, 3)), std::invalid_argument);
}

TEST(ClosedLoopRate, SpectralRadiusOfMatricesWithKnownEigenvalues) {
  // V diag(blocks) V^-1 with a rotation-scaling block of modulus 5 (eigenvalues 3 +- 4i) and real
  // eigenvalues -4.5 and 2: rho = 5.
  Eigen::Matrix4d D = Eigen::Matrix4d::Zero();
  D.topLeftCorner<2, 2>() << 3, -4, 4, 3;
  D(2, 2) = -4.5;
  D(3, 3) = 2;
  Rng rng(3);
  Eigen::Matrix4d V;
  for (int k = 0; k < 16; ++k) V.data()[k] = rng.Uniform(-1, 1);
  V += 3 * Eigen::Matrix4d::Identity();
  EXPECT_NEAR(SpectralRadius(V * D * V.inverse()), 5.0, 1e-9);
  EXPECT_EQ(SpectralRadius(Eigen::MatrixXd(0, 0)), 0.0);
  Eigen::MatrixXd bad = Eigen::MatrixXd::Identity(3, 3);
  bad(1, 2) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(SpectralRadius(bad), kInf);
  EXPECT_THROW(SpectralRadius(Eigen::MatrixXd::Zero(2, 3)), std::invalid_argument);
}

TEST(ClosedLoopRate, StepsPerSampleKeepsStepTimesRateAtMostTheLimit) {
  ASSERT_EQ(kStepRateLimit, 1.0);
  // Slow loops keep the base count; beyond it, the fewest equal steps with h rho <= 1.
  EXPECT_EQ(StepsPerSample(1e-3, 10.0, 2), 2.0);
  EXPECT_EQ(StepsPerSample(1e-3, 2000.0, 2), 2.0);   // h rho = 1 exactly
  EXPECT_EQ(StepsPerSample(1e-3, 2000.5, 2), 3.0);
  EXPECT_EQ(StepsPerSample(1e-3, 4000.0, 2), 4.0);   // T rho a whole number: not one more
  EXPECT_EQ(StepsPerSample(1e-3, 4001.0, 2), 5.0);
  EXPECT_EQ(StepsPerSample(2e-3, 0.0, 1), 1.0);
  EXPECT_EQ(StepsPerSample(1e-3, 1e7, 2), 10000.0);  // above MaxStepsPerSample: the caller refuses
  EXPECT_GT(StepsPerSample(1e-3, 1e7, 2), MaxStepsPerSample(1e-3));
  // The shortest step is 5e-7 s, whatever the interval: 2000 steps at 1 kHz, 2e6 at 1 Hz.
  EXPECT_EQ(MaxStepsPerSample(1e-3), 2000.0);
  EXPECT_EQ(MaxStepsPerSample(1.0), 2e6);
  EXPECT_EQ(MaxStepsPerSample(1e-7), 1.0);
  EXPECT_EQ(MaxStepsPerSample(1e6), 1e9);
  EXPECT_THROW(MaxStepsPerSample(0.0), std::invalid_argument);
  EXPECT_EQ(StepsPerSample(1e-3, kInf, 2), kInf);
  for (int s = 1; s < 50; ++s) {
    const double rho = 1234.5 * s, steps = StepsPerSample(1e-2, rho, 1);
    EXPECT_LE(1e-2 / steps * rho, kStepRateLimit);
    EXPECT_GT(1e-2 / (steps - 1) * rho, kStepRateLimit);
  }
  EXPECT_THROW(StepsPerSample(0.0, 1.0, 1), std::invalid_argument);
  EXPECT_THROW(StepsPerSample(1e-3, -1.0, 1), std::invalid_argument);
  EXPECT_THROW(StepsPerSample(1e-3, std::numeric_limits<double>::quiet_NaN(), 1), std::invalid_argument);
  EXPECT_THROW(StepsPerSample(1e-3, 1.0, 0), std::invalid_argument);
}

}  // namespace
}  // namespace inertial
