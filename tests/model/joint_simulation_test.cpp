#include "inertial/model/joint_simulation.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <limits>
#include <regex>
#include <string>
#include <utility>
#include <vector>

#include "inertial/inertia/closed_form_bodies.hpp"
#include "inertial/model/fourier_trajectory.hpp"
#include "inertial/model/kinematic_tree.hpp"
#include "test_support.hpp"

namespace inertial {
namespace {

using testing::Rng;

constexpr double kPi = 3.14159265358979323846;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// A random branched tree of 7 bodies (revolute and prismatic joints with random unit axes, one
// fixed joint, random origins and random consistent inertias) and a geared rotor on the base
// driving the first joint: 6 DOFs.
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
  JointModel r;
  r.name = "rotor_of_b0";
  r.R_parent_joint = rng.Rotation();
  r.axis = rng.UniformVector<3>(-1, 1).normalized();
  // One draw per statement, in the order the x86-64 build drew them (see testing::Rng).
  const Pose rotor_pose{rng.Rotation(), rng.UniformVector<3>(-0.01, 0.01)};
  const Vector3 rotor_L = rng.UniformVector<3>(1e-5, 1e-4);
  const InertialParams rotor = BodyFromSecondMoments(0.3, rotor_L, rotor_pose);
  tree.AddRotor(r.name, -1, r, rotor, 0, 8.0);
  return tree;
}

Eigen::VectorXd RandomVector(Rng& rng, int n, double lo, double hi) {
  return Eigen::VectorXd::NullaryExpr(n, [&] { return rng.Uniform(lo, hi); });
}

JointDynamicsFn TreeDynamics(const KinematicTree& tree, const Vector3& g) {
  return [&tree, g](const Eigen::VectorXd& q, const Eigen::VectorXd& qd, const Eigen::VectorXd& qdd) {
    return tree.InverseDynamics(q, qd, qdd, g);
  };
}

JointReferenceFn Reference(const FourierTrajectory& traj) {
  return [&traj](double t) { return traj.Evaluate(t); };
}

const JointControllerFn kPassive = [](double, const Eigen::VectorXd& q, const Eigen::VectorXd&) {
  return Eigen::VectorXd::Zero(q.size()).eval();
};

// T + V of every body (rotors included): T = sum 0.5 v^T M v, V = -sum m g . c.
double TotalEnergy(const KinematicTree& tree, const Vector3& g, const Eigen::VectorXd& q, const Eigen::VectorXd& qd) {
  const std::vector<Vector6> v = tree.BodyVelocities(q, qd);
  const std::vector<SpatialTransform> pose = tree.BodyPoses(q);
  double E = 0.0;
  for (int i = 0; i < tree.num_bodies(); ++i) {
    const InertialParams& I = tree.inertia(i);
    E += 0.5 * v[i].dot(I.spatial_inertia() * v[i]);
    E -= I.mass() * g.dot(pose[i].p_AB + pose[i].R_AB * I.com());
  }
  return E;
}

// A passive three-link spatial pendulum with a geared rotor on the first joint, gravity -z.
KinematicTree ThreeLinkPendulum() {
  KinematicTree tree;
  const Vector3 axes[3] = {Vector3::UnitX(), Vector3(0, 0.6, 0.8), Vector3::UnitY()};
  int parent = -1;
  for (int i = 0; i < 3; ++i) {
    JointModel j;
    j.name = "j" + std::to_string(i);
    j.p_parent_joint = i == 0 ? Vector3::Zero() : Vector3(0, 0, -0.3);
    j.axis = axes[i];
    parent = tree.AddBody("l" + std::to_string(i), parent, j,
                          SolidBox(1.0 - 0.2 * i, 0.04, 0.05, 0.3, Pose{Matrix3::Identity(), Vector3(0.02, 0, -0.15)}));
  }
  JointModel r;
  r.name = "rotor";
  r.axis = Vector3::UnitX();
  tree.AddRotor("rotor", -1, r, SolidCylinder(0.2, 0.02, 0.02, Pose{Eigen::AngleAxisd(kPi / 2, Vector3::UnitY())
                                                                        .toRotationMatrix(),
                                                                    Vector3::Zero()}),
                0, 5.0);
  return tree;
}

// (a) Forward dynamics inverts the recursive Newton-Euler inverse dynamics, with joint effects
// (viscous friction, armature) added to the rigid bodies.
TEST(JointSimulation, ForwardDynamicsInvertsInverseDynamics) {
  Rng rng(11);
  for (int trial = 0; trial < 50; ++trial) {
    const KinematicTree tree = RandomTree(rng);
    const int n = tree.num_dofs();
    ASSERT_EQ(n, 6);
    const Vector3 g = rng.UniformVector<3>(-10, 10);
    const Eigen::VectorXd b = RandomVector(rng, n, 0.0, 2.0), Ia = RandomVector(rng, n, 0.0, 0.1);
    const JointDynamicsFn id = [&](const Eigen::VectorXd& q, const Eigen::VectorXd& qd, const Eigen::VectorXd& qdd) {
      return (tree.InverseDynamics(q, qd, qdd, g) + b.cwiseProduct(qd) + Ia.cwiseProduct(qdd)).eval();
    };
    const Eigen::VectorXd q = RandomVector(rng, n, -3, 3), qd = RandomVector(rng, n, -3, 3),
                          qdd = RandomVector(rng, n, -3, 3);
    const Eigen::VectorXd tau = id(q, qd, qdd);
    const Eigen::VectorXd qdd_fd = ForwardDynamics(id, q, qd, tau);
    EXPECT_LT((qdd_fd - qdd).cwiseAbs().maxCoeff(), 1e-9) << qdd_fd.transpose() << "\n" << qdd.transpose();
  }
}

// (b) Passive motion conserves T + V up to the integrator's error, which shrinks as h^4 (RK4).
TEST(JointSimulation, PassivePendulumConservesEnergyToFourthOrder) {
  const KinematicTree tree = ThreeLinkPendulum();
  const Vector3 g(0, 0, -9.81);
  const Eigen::Vector3d q0(1.2, -0.7, 2.0), qd0(0.5, 1.0, -2.0);
  const double E0 = TotalEnergy(tree, g, q0, qd0);
  const double scale = 1.0 * 9.81 * 0.9;  // m g L, the energy scale of the motion [J]
  auto max_energy_error = [&](double step) {
    JointSimulationOptions options;
    options.duration = 5.0;
    options.sample_rate_hz = 100.0;
    options.internal_step = step;
    const JointSamples s = SimulateJoints(TreeDynamics(tree, g), kPassive, q0, qd0, options);
    EXPECT_EQ(s.size(), 501);
    double err = 0.0;
    for (int i = 0; i < s.size(); ++i) {
      err = std::max(err, std::abs(TotalEnergy(tree, g, s.q.row(i).transpose(), s.qd.row(i).transpose()) - E0));
    }
    return err / scale;
  };
  const double e_fine = max_energy_error(2e-4), e_coarse = max_energy_error(2e-3), e_half = max_energy_error(1e-3);
  std::cout << "relative energy error: h = 2 ms " << e_coarse << ", 1 ms " << e_half << ", 0.2 ms " << e_fine << "\n";
  EXPECT_LT(e_fine, 1e-8);
  // Halving the step divides the error by about 2^4.
  EXPECT_GT(e_coarse / e_half, 10.0);
  EXPECT_LT(e_coarse / e_half, 24.0);
}

// (c) Small oscillations of a pendulum (sphere of mass m, radius r at distance l, plus a geared
// rotor of axial inertia Ir, ratio N) have the period 2 pi sqrt(I / (m g l)) (1 + theta0^2 / 16 + ...)
// with I = 2/5 m r^2 + m l^2 + N^2 Ir.
TEST(JointSimulation, SmallAnglePendulumPeriod) {
  const double m = 1.3, r = 0.05, l = 0.7, g = 9.81, N = 7.0, theta0 = 0.05;
  KinematicTree tree;
  JointModel j;
  j.name = "pivot";
  tree.AddBody("bob", -1, j, SolidSphere(m, r, Pose{Matrix3::Identity(), Vector3(l, 0, 0)}));
  j.name = "rotor";
  tree.AddRotor("rotor", -1, j, SolidCylinder(0.2, 0.03, 0.02), 0, N);
  const double I = 0.4 * m * r * r + m * l * l + N * N * 0.5 * 0.2 * 0.03 * 0.03;
  const double period = 2 * kPi * std::sqrt(I / (m * g * l)) * (1 + theta0 * theta0 / 16);

  JointSimulationOptions options;
  options.duration = 6 * period;
  const Eigen::VectorXd q_start = Eigen::VectorXd::Constant(1, -kPi / 2 + theta0);  // hanging at -pi/2
  const JointSamples s =
      SimulateJoints(TreeDynamics(tree, Vector3(0, -g, 0)), kPassive, q_start, Eigen::VectorXd::Zero(1), options);
  // Upward zero crossings of q + pi/2, linearly interpolated.
  std::vector<double> crossings;
  for (int i = 1; i < s.size(); ++i) {
    const double a = s.q(i - 1, 0) + kPi / 2, b = s.q(i, 0) + kPi / 2;
    if (a < 0 && b >= 0) crossings.push_back(s.t[i - 1] + (s.t[i] - s.t[i - 1]) * a / (a - b));
  }
  ASSERT_GE(crossings.size(), 5u);
  const double measured = (crossings.back() - crossings.front()) / (crossings.size() - 1);
  EXPECT_NEAR(measured / period, 1.0, 1e-6) << measured << " vs " << period;
  // Amplitude is kept (no numerical damping to speak of).
  EXPECT_NEAR(s.q.col(0).maxCoeff(), -kPi / 2 + theta0, 1e-6);
}

// (d) With the true model in the computed torque, the plant follows the reference up to the zero-order
// hold; with an approximate model (masses 20 % off, no friction), feedback keeps errors small.
// At every sample, the plant's dynamics hold exactly: id(q, qd, qdd) = tau.
TEST(JointSimulation, TrackingFollowsTheReference) {
  Rng rng(5);
  const KinematicTree tree = RandomTree(rng);
  const int n = tree.num_dofs();
  const Vector3 g(0, 0, -9.81);
  const Eigen::VectorXd b = RandomVector(rng, n, 0.1, 1.0);
  const JointDynamicsFn plant = [&](const Eigen::VectorXd& q, const Eigen::VectorXd& qd, const Eigen::VectorXd& qdd) {
    return (tree.InverseDynamics(q, qd, qdd, g) + b.cwiseProduct(qd)).eval();
  };
  KinematicTree wrong;
  for (int i = 0; i < tree.num_bodies(); ++i) {
    const InertialParams body = InertialParams::FromVector(0.8 * tree.inertia(i).vector());
    if (tree.is_rotor(i)) {
      wrong.AddRotor(tree.body_name(i), tree.parent(i), tree.joint(i), body, tree.dof_index(i), tree.gear_ratio(i));
    } else {
      wrong.AddBody(tree.body_name(i), tree.parent(i), tree.joint(i), body);
    }
  }
  const FourierTrajectory traj = RandomFourierTrajectory(n, 5, 0.2, 0.5, 42);
  JointSimulationOptions options;
  options.duration = 5.0;
  options.kp = Eigen::VectorXd::Constant(n, 400.0);
  options.kd = Eigen::VectorXd::Constant(n, 40.0);
  const std::vector<std::string> names = {"a", "b", "c", "d", "e", "f"};

  auto tracking_errors = [&](const JointSamples& s) {
    double eq = 0, ev = 0;
    for (int i = 0; i < s.size(); ++i) {
      const JointTrajectoryPoint ref = traj.Evaluate(s.t[i]);
      eq = std::max(eq, (s.q.row(i).transpose() - ref.q).cwiseAbs().maxCoeff());
      ev = std::max(ev, (s.qd.row(i).transpose() - ref.qd).cwiseAbs().maxCoeff());
      const Eigen::VectorXd tau = plant(s.q.row(i).transpose(), s.qd.row(i).transpose(), s.qdd.row(i).transpose());
      EXPECT_LT((tau - s.tau.row(i).transpose()).cwiseAbs().maxCoeff(), 1e-9) << "t = " << s.t[i];
    }
    return std::pair{eq, ev};
  };

  const JointSamples exact = SimulateTracking(plant, plant, Reference(traj), options, names);
  ASSERT_EQ(exact.size(), 5001);
  EXPECT_EQ(exact.joint_names, names);
  EXPECT_NEAR(exact.t[5000], 5.0, 1e-12);
  const auto [eq_exact, ev_exact] = tracking_errors(exact);
  const JointSamples approx =
      SimulateTracking(plant, TreeDynamics(wrong, g), Reference(traj), options, names);
  const auto [eq_approx, ev_approx] = tracking_errors(approx);
  std::cout << "max tracking error, true model: " << eq_exact << " (q), " << ev_exact
            << " (qd); approximate model: " << eq_approx << " (q), " << ev_approx << " (qd)\n";
  EXPECT_LT(eq_exact, 1e-4);
  EXPECT_LT(ev_exact, 1e-2);
  EXPECT_LT(eq_approx, 0.05);
  EXPECT_GT(eq_approx, 10 * eq_exact);  // the model error shows, as it should
}

// Inverse-dynamics data lie exactly on the reference with tau = id(q_ref, qd_ref, qdd_ref).
TEST(JointSimulation, SampleTrajectoryIsTheReference) {
  Rng rng(3);
  const KinematicTree tree = RandomTree(rng);
  const FourierTrajectory traj = RandomFourierTrajectory(tree.num_dofs(), 3, 0.1, 0.5, 1);
  JointSimulationOptions options;
  options.start_time = 1.0;
  options.duration = 2.0;
  options.sample_rate_hz = 200.0;
  const JointDynamicsFn id = TreeDynamics(tree, Vector3(0, 0, -9.81));
  const JointSamples s = SampleTrajectory(id, Reference(traj), options);
  ASSERT_EQ(s.size(), 401);
  EXPECT_TRUE(s.joint_names.empty());
  for (int i : {0, 123, 400}) {
    EXPECT_NEAR(s.t[i], 1.0 + i / 200.0, 1e-12);
    const JointTrajectoryPoint p = traj.Evaluate(s.t[i]);
    EXPECT_EQ(s.q.row(i).transpose(), p.q);
    EXPECT_EQ(s.qdd.row(i).transpose(), p.qdd);
    EXPECT_EQ(s.tau.row(i).transpose(), id(p.q, p.qd, p.qdd));
  }
}

// Noise has the requested standard deviations, zero mean, and is reproducible from its seed.
TEST(JointSimulation, GaussianNoiseStatisticsAndSeed) {
  JointSamples clean;
  const int N = 20000, n = 3;
  clean.joint_names = {"x", "y", "z"};
  clean.t = Eigen::VectorXd::LinSpaced(N, 0.0, 1.0);
  clean.q = clean.qd = clean.qdd = clean.tau = Eigen::MatrixXd::Constant(N, n, 2.0);
  const SampleNoise sigma{1e-3, 0.01, 0.5, 0.0};
  const JointSamples noisy = AddGaussianNoise(clean, sigma, 99);
  auto check = [&](const Eigen::MatrixXd& m, double sd) {
    const Eigen::ArrayXXd e = (m.array() - 2.0);
    const double mean = e.mean(), std_dev = std::sqrt((e - mean).square().mean());
    // Sample mean and standard deviation of N n draws: 4-sigma bands.
    EXPECT_LT(std::abs(mean), 4 * sd / std::sqrt(double(N * n)) + 1e-300);
    EXPECT_NEAR(std_dev, sd, 4 * sd / std::sqrt(2.0 * N * n) + 1e-300);
  };
  check(noisy.q, sigma.q);
  check(noisy.qd, sigma.qd);
  check(noisy.qdd, sigma.qdd);
  EXPECT_EQ(noisy.tau, clean.tau);
  EXPECT_EQ(noisy.t, clean.t);
  EXPECT_EQ(noisy.joint_names, clean.joint_names);
  EXPECT_EQ(AddGaussianNoise(clean, sigma, 99).qdd, noisy.qdd);
  EXPECT_NE(AddGaussianNoise(clean, sigma, 100).qdd, noisy.qdd);
}

// Computed torque with the plant as its own model makes every joint's error the linear loop e'' +
// kd e' + kp e = 0, whatever the robot: on a random tree with a geared rotor, gravity, viscous and
// (smoothed) Coulomb friction, a reference that steps by d just after the start is approached as
// the closed form of a critically damped loop of bandwidth w (kp = w^2, kd = 2 w):
// e(t) = d (1 + w t) e^(-w t), joint by joint.
TEST(JointSimulation, ComputedTorqueMakesEveryJointsErrorTheLinearLoop) {
  Rng rng(8);
  const KinematicTree tree = RandomTree(rng);
  const int n = tree.num_dofs();
  const Vector3 g(0, 0, -9.81);
  const Eigen::VectorXd b = RandomVector(rng, n, 0.1, 1.0), bc = RandomVector(rng, n, 0.1, 0.5);
  const JointDynamicsFn plant = [&](const Eigen::VectorXd& q, const Eigen::VectorXd& qd, const Eigen::VectorXd& qdd) {
    const Eigen::VectorXd coulomb = bc.cwiseProduct((qd / 0.05).array().tanh().matrix());
    return (tree.InverseDynamics(q, qd, qdd, g) + b.cwiseProduct(qd) + coulomb).eval();
  };
  const FourierTrajectory traj = RandomFourierTrajectory(n, 3, 0.2, 0.5, 6);
  const Eigen::VectorXd d = RandomVector(rng, n, -0.05, 0.05);
  const JointReferenceFn stepped = [&](double t) {
    JointTrajectoryPoint p = traj.Evaluate(t);
    if (t > 0) p.q += d;
    return p;
  };
  const double w = 20;
  JointSimulationOptions options;
  options.duration = 1.0;
  options.kp = Eigen::VectorXd::Constant(1, w * w);
  options.kd = Eigen::VectorXd::Constant(1, 2 * w);
  const JointSamples s = SimulateTracking(plant, plant, stepped, options);
  double worst = 0;
  for (int i = 1; i < s.size(); ++i) {
    const double t = s.t[i];
    const Eigen::VectorXd e = traj.Evaluate(t).q + d - s.q.row(i).transpose();
    worst = std::max(worst, (e - d * (1 + w * t) * std::exp(-w * t)).cwiseAbs().maxCoeff());
  }
  // The command is held over steps of 2e-4 s (h w = 0.004): the response lags the continuous one
  // by about half a step, an error of order h w |d| / 2.
  std::cout << "largest departure from the linear loop: " << worst << " (steps of " << d.cwiseAbs().maxCoeff() << ")\n";
  EXPECT_LT(worst, 4e-3 * d.cwiseAbs().maxCoeff());
  EXPECT_TRUE(s.q.row(0).transpose() == traj.Evaluate(0).q);  // starts on the unstepped reference
}

// Every sample interval gets enough steps for its loop: a loop of w = 5000 1/s on one joint
// (rho = w) at 1 kHz gets ceil(1e-3 w) = 5 steps where the base step (5e-4 s, h w = 2.5, beyond
// the held PD loop's limit 1 / zeta = 1.43) would diverge, and tracks its reference.
TEST(JointSimulation, StepsFollowTheClosedLoopsRate) {
  const double I = 1e-3, w = 5000, zeta = 0.7;
  const JointDynamicsFn inertia = [I](const Eigen::VectorXd&, const Eigen::VectorXd&, const Eigen::VectorXd& qdd) {
    return (I * qdd).eval();
  };
  const FourierTrajectory traj = RandomFourierTrajectory(1, 3, 1.0, 0.5, 4);
  JointSimulationOptions options;
  options.duration = 0.5;
  options.sample_rate_hz = 1000;
  options.internal_step = 5e-4;
  options.kp = Eigen::VectorXd::Constant(1, w * w);
  options.kd = Eigen::VectorXd::Constant(1, 2 * zeta * w);
  JointSimulationStats stats;
  const JointSamples s = SimulateTracking(inertia, inertia, Reference(traj), options, {}, &stats);
  EXPECT_NEAR(stats.max_rate, w, 1e-6 * w);
  EXPECT_EQ(stats.min_steps_per_sample, 5);
  EXPECT_EQ(stats.max_steps_per_sample, 5);
  EXPECT_EQ(stats.total_steps, 5 * 500);
  double worst = 0;
  for (int i = 0; i < s.size(); ++i) worst = std::max(worst, std::abs(s.q(i, 0) - traj.Evaluate(s.t[i]).q[0]));
  EXPECT_LT(worst, 1e-6);  // the feedforward is exact: only the hold deviates

  // Coulomb friction 0.1 tanh(qd / 0.01) on a light joint (1e-4 kg m^2) with a spring (1 N m/rad),
  // released at rest from q = 1: at every velocity reversal the friction's slope 10 N m s/rad makes
  // a real mode near -1e5 1/s, which gets ceil(1e-3 * 1e5) = 100 steps; between reversals the
  // base 2. The oscillation decays by 2 bc / k = 0.2 rad per half cycle and sticks within the
  // friction band |q| < bc / k = 0.1 (creeping at the smoothed friction's velocity).
  const JointDynamicsFn dry = [](const Eigen::VectorXd& q, const Eigen::VectorXd& qd, const Eigen::VectorXd& qdd) {
    return Eigen::VectorXd::Constant(1, 1e-4 * qdd[0] + 0.1 * std::tanh(qd[0] / 0.01) + q[0]);
  };
  options.duration = 0.3;
  const JointSamples free = SimulateJoints(dry, kPassive, Eigen::VectorXd::Ones(1), Eigen::VectorXd::Zero(1), options,
                                           {}, &stats);
  const double peak = (10.0 + std::sqrt(100.0 - 4e-4)) / 2e-4;  // 1e-4 s^2 + 10 s + 1 = 0
  EXPECT_NEAR(stats.max_rate, peak, 1e-4 * peak);
  EXPECT_EQ(stats.max_steps_per_sample, 100);
  EXPECT_EQ(stats.min_steps_per_sample, 2);
  EXPECT_LT(std::abs(free.q(free.size() - 1, 0)), 0.1);
  EXPECT_LT(free.qd.cwiseAbs().maxCoeff(), 101.0);  // at most the undamped w0 q0 = 100 rad/s
  for (int i = 0; i < free.size(); i += 7) {
    EXPECT_NEAR(dry(free.q.row(i).transpose(), free.qd.row(i).transpose(), free.qdd.row(i).transpose())[0],
                free.tau(i, 0), 1e-12);
  }
}

// Failures past the initial state are divergences, with the time and the reason; a model that is
// not one at the initial state is named as the model's error.
TEST(JointSimulation, DivergenceIsReportedAsSuch) {
  JointSimulationOptions options;
  options.duration = 2.0;
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(1), one = Eigen::VectorXd::Ones(1);
  // A joint of 1e-7 kg m^2 with 1 N m s/rad of damping: a real mode at -1e7 1/s, which would need
  // 1e4 steps per 1 ms sample.
  const JointDynamicsFn stiff = [](const Eigen::VectorXd&, const Eigen::VectorXd& qd, const Eigen::VectorXd& qdd) {
    return (1e-7 * qdd + qd).eval();
  };
  try {
    SimulateJoints(stiff, kPassive, zero, one, options);
    ADD_FAILURE() << "no exception";
  } catch (const SimulationDiverged& e) {
    EXPECT_EQ(e.time(), 0.0);
    // 10000 steps, or 10001 where the differenced slope rounds a few 1e-9 above 1.
    EXPECT_TRUE(std::regex_match(std::string(e.what()),
                                 std::regex("the simulation diverged at t = 0 s \\(the loop's fastest mode is 1e\\+07 "
                                            "1/s: RK4 would need 1000[01] steps per sample of 0\\.001 s, more than the "
                                            "2000 of the shortest step 5e-07 s; max \\|q\\| = 0, max \\|qd\\| = 1\\)")))
        << e.what();
  }
  // qdd = 10 qd^2 from qd = 1: qd = 1 / (1 - 10 t) runs away at t = 0.1 s.
  const JointDynamicsFn blow_up = [](const Eigen::VectorXd&, const Eigen::VectorXd& qd, const Eigen::VectorXd& qdd) {
    return (qdd - 10.0 * qd.cwiseProduct(qd)).eval();
  };
  try {
    SimulateJoints(blow_up, kPassive, zero, one, options);
    ADD_FAILURE() << "no exception";
  } catch (const SimulationDiverged& e) {
    EXPECT_NEAR(e.time(), 0.1, 1e-3);
    EXPECT_EQ(std::string(e.what()).rfind("the simulation diverged at t = ", 0), 0u) << e.what();
  }
  // The mass 1 - q of a joint moving at qd = 1 from q = 0 vanishes at t = 1 s.
  const JointDynamicsFn vanishing = [](const Eigen::VectorXd& q, const Eigen::VectorXd&, const Eigen::VectorXd& qdd) {
    return ((1.0 - q.array()) * qdd.array()).matrix().eval();
  };
  try {
    SimulateJoints(vanishing, kPassive, zero, one, options);
    ADD_FAILURE() << "no exception";
  } catch (const SimulationDiverged& e) {
    EXPECT_NEAR(e.time(), 1.0, 1e-3);
    EXPECT_NE(std::string(e.what()).find("the mass matrix (qdd coefficient of the inverse dynamics) is not positive "
                                         "definite at the state reached, max |q| = 1"),
              std::string::npos)
        << e.what();
  }
  // A mass matrix that is not positive definite at the start: the model's error, no divergence.
  const JointDynamicsFn negative = [](const Eigen::VectorXd&, const Eigen::VectorXd&, const Eigen::VectorXd& qdd) {
    return (-qdd).eval();
  };
  try {
    SimulateJoints(negative, kPassive, zero, one, options);
    ADD_FAILURE() << "no exception";
  } catch (const SimulationDiverged& e) {
    ADD_FAILURE() << "reported as a divergence: " << e.what();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("is not positive definite at the initial state (a model error, not a "
                                         "diverged simulation)"),
              std::string::npos)
        << e.what();
  }
}

// (f) Errors: bad options and sizes, a singular mass matrix, a diverging state.
TEST(JointSimulation, RejectsBadInput) {
  const JointDynamicsFn unit_mass = [](const Eigen::VectorXd&, const Eigen::VectorXd&, const Eigen::VectorXd& qdd) {
    return qdd;
  };
  const Eigen::VectorXd one = Eigen::VectorXd::Ones(1), two = Eigen::VectorXd::Ones(2);
  EXPECT_THROW(ForwardDynamics(unit_mass, one, two, one), std::invalid_argument);
  const JointDynamicsFn massless = [](const Eigen::VectorXd& q, const Eigen::VectorXd&, const Eigen::VectorXd&) {
    return Eigen::VectorXd::Zero(q.size()).eval();
  };
  EXPECT_THROW(ForwardDynamics(massless, one, one, one), std::invalid_argument);
  const JointDynamicsFn wrong_size = [](const Eigen::VectorXd&, const Eigen::VectorXd&, const Eigen::VectorXd&) {
    return Eigen::VectorXd::Ones(3).eval();
  };
  EXPECT_THROW(ForwardDynamics(wrong_size, one, one, one), std::invalid_argument);

  JointSimulationOptions ok;
  ok.duration = 0.01;
  EXPECT_EQ(SimulateJoints(unit_mass, kPassive, one, one, ok).size(), 11);
  for (auto bad : {+[](JointSimulationOptions& o) { o.internal_step = 0.0; },
                   +[](JointSimulationOptions& o) { o.internal_step = -1e-3; },
                   +[](JointSimulationOptions& o) { o.sample_rate_hz = 0.0; },
                   +[](JointSimulationOptions& o) { o.duration = -1.0; },
                   +[](JointSimulationOptions& o) { o.start_time = kNaN; }}) {
    JointSimulationOptions options = ok;
    bad(options);
    EXPECT_THROW(SimulateJoints(unit_mass, kPassive, one, one, options), std::invalid_argument);
  }
  EXPECT_THROW(SimulateJoints(unit_mass, kPassive, one, two, ok), std::invalid_argument);
  EXPECT_THROW(SimulateJoints(unit_mass, kPassive, one, one, ok, {"a", "b"}), std::invalid_argument);
  // The refused value is named with its significant digits (a fixed 6 decimals would show -1e-7 as
  // -0.000000).
  JointSimulationOptions tiny = ok;
  tiny.internal_step = -1e-7;
  try {
    SimulateJoints(unit_mass, kPassive, one, one, tiny);
    ADD_FAILURE() << "a negative internal_step was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("internal_step must be positive and finite, got -1e-07"), std::string::npos)
        << e.what();
  }

  const FourierTrajectory traj = RandomFourierTrajectory(2, 2, 1.0, 0.1, 0);
  JointSimulationOptions gains = ok;
  gains.kp = Eigen::VectorXd::Ones(3);
  EXPECT_THROW(SimulateTracking(unit_mass, unit_mass, Reference(traj), gains), std::invalid_argument);
  gains.kp = -Eigen::VectorXd::Ones(1);
  EXPECT_THROW(SimulateTracking(unit_mass, unit_mass, Reference(traj), gains), std::invalid_argument);
  EXPECT_NO_THROW(SimulateTracking(unit_mass, unit_mass, Reference(traj), ok));

  // The error names the simulation time: qdd = 10 qd^2 from qd = 1 blows up at t = 0.1 s; a plant
  // whose model is undefined beyond q = 1.5 (NaN) is left at t = 0.5 s. Both are past the initial
  // state: divergences.
  auto error_time = [&](const JointDynamicsFn& plant, const std::string& expected_words) {
    JointSimulationOptions longer = ok;
    longer.duration = 1.0;
    try {
      SimulateJoints(plant, kPassive, one, one, longer);
      ADD_FAILURE() << "no exception";
    } catch (const std::invalid_argument& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(expected_words), std::string::npos) << what;
      const std::size_t at = what.find("t = ");
      if (at != std::string::npos) return std::stod(what.substr(at + 4));
      ADD_FAILURE() << what;
    }
    return kNaN;
  };
  const JointDynamicsFn blow_up = [](const Eigen::VectorXd&, const Eigen::VectorXd& qd, const Eigen::VectorXd& qdd) {
    return (qdd - 10.0 * qd.cwiseProduct(qd)).eval();
  };
  EXPECT_NEAR(error_time(blow_up, "the simulation diverged at t = "), 0.1, 1e-3);
  const JointDynamicsFn undefined = [](const Eigen::VectorXd& q, const Eigen::VectorXd&, const Eigen::VectorXd& qdd) {
    return (qdd + 0.0 * (1.5 - q.array()).sqrt().matrix()).eval();
  };
  EXPECT_NEAR(error_time(undefined, "non-finite"), 0.5, 1e-3);
  EXPECT_NEAR(error_time(undefined, "the simulation diverged at t = "), 0.5, 1e-3);

  EXPECT_THROW(AddGaussianNoise(JointSamples(), SampleNoise{-1.0, 0, 0, 0}, 1), std::invalid_argument);
  EXPECT_THROW(AddGaussianNoise(JointSamples(), SampleNoise{0, 0, 0, kNaN}, 1), std::invalid_argument);

  FourierTrajectory bad = traj;
  bad.b = Eigen::MatrixXd::Zero(2, 3);
  EXPECT_THROW(bad.Evaluate(0.0), std::invalid_argument);
  bad = traj;
  bad.base_frequency_hz = 0.0;
  EXPECT_THROW(bad.Evaluate(0.0), std::invalid_argument);
  EXPECT_THROW(traj.Evaluate(std::numeric_limits<double>::infinity()), std::invalid_argument);
  EXPECT_THROW(RandomFourierTrajectory(0, 3, 1.0, 0.1, 0), std::invalid_argument);
  EXPECT_THROW(RandomFourierTrajectory(2, 0, 1.0, 0.1, 0), std::invalid_argument);
  EXPECT_THROW(RandomFourierTrajectory(2, 3, -1.0, 0.1, 0), std::invalid_argument);
  EXPECT_THROW(RandomFourierTrajectory(2, 3, 1.0, 0.0, 0), std::invalid_argument);
}

}  // namespace
}  // namespace inertial
