// Embedding the online estimator in a control loop, with the embeddable core alone (Eigen, no
// files, no I/O library: the package's inertial::estimation): a simulated 7-DOF arm, the one of
// examples/arm7.urdf written out in code (bundled_robots.hpp), carries an unknown 2 kg payload
// on its flange; the controller is computed-torque control with the current estimate (tau = A(q,
// qd, qdd_ref + Kp e + Kd de) w_hat, the estimated robot's inverse dynamics), and the natural
// gradient law learns the payload from every control tick, every estimate a consistent body. The
// tracking error falls as the estimate converges; with the prior kept fixed it stays large (the
// flange sags under the unmodelled 1.5 kg). Everything per tick is allocation-free.
//
//   ./build/examples/adaptive_control [seconds]      (default 10)
//
// Prints the RMS tracking error [rad] per 50 ms window with the payload prior fixed and with the
// estimator adapting, and the estimated payload mass [kg]. Built against the installed package by
// tests/package (find_package(inertial), target_link_libraries(... inertial::estimation)).
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <utility>
#include <vector>

#include "bundled_robots.hpp"  // next to this file
#include "inertial/estimation/online/online_joint_estimator.hpp"
#include "inertial/model/fourier_trajectory.hpp"
#include "inertial/model/joint_simulation.hpp"

using namespace inertial;

int main(int argc, char** argv) {
  const double seconds = argc > 1 ? std::atof(argv[1]) : 10.0;
  if (!(seconds > 0 && seconds < 1e5)) {
    std::fprintf(stderr, "usage: adaptive_control [seconds > 0]\n");
    return 2;
  }
  // The model the controller and estimator know: the arm's links plus a payload of unknown inertia
  // on tool0, the flange 4.5 cm along link7's z (prior: a 0.5 kg sphere). The truth: the same links
  // with a 2 kg body 5 cm off the flange.
  const RobotDynamics model = examples::Arm7().Dynamics("payload@tool0:mass=0.5");
  const int n = model.num_dofs(), payload = static_cast<int>(model.bodies().size()) - 1;
  Eigen::VectorXd x_true = Eigen::VectorXd::Zero(model.num_parameters());
  x_true.segment<10>(10 * payload) << 0.693, 0.2, -0.3, 0.4, 0.1, 0.0, 0.0, 0.01, -0.01, 0.05;  // ~2 kg
  const double true_mass = model.BodyInertia(payload, x_true).mass();

  // One run; per 50 ms window: RMS tracking error and the estimated payload mass.
  auto run = [&](bool adapt) {
    std::vector<std::pair<double, double>> windows;
    OnlineEstimatorOptions options;
    // The natural gradient law (gradient_estimator.hpp): one step per tick on the objective of
    // every tick so far, no solve, no covariance; gauss_newton (the objective re-solved from its
    // statistics) would do as well, with its solves between ticks.
    options.kind = EstimatorKind::kGradient;
    // The links are known from CAD (held at their priors); the payload is not.
    options.fit.solve.frozen_bodies.assign(model.bodies().size(), true);
    options.fit.solve.frozen_bodies[payload] = false;
    OnlineJointEstimator estimator(model, Eigen::VectorXd::Zero(model.num_parameters()), options);

    const double dt = 1e-3;  // 1 kHz control and estimation
    const FourierTrajectory reference = RandomFourierTrajectory(n, 4, 0.2, 0.6, 7);
    const double kp = 100.0, kd = 20.0;
    Eigen::VectorXd q = reference.Evaluate(0).q, qd = reference.Evaluate(0).qd, qdd_cmd(n), tau(n), qd_prev(n), q_prev(n);
    TreeWorkspace workspace = model.MakeWorkspace();
    Eigen::MatrixXd A(n, model.num_features());
    JointSample sample{0.0, Eigen::VectorXd(n), Eigen::VectorXd(n), Eigen::VectorXd(n), Eigen::VectorXd(n)};
    // The plant: the true robot's forward dynamics (its inverse dynamics from coefficients computed once).
    const Eigen::VectorXd w_true = model.Coefficients(x_true);
    const JointDynamicsFn true_robot = [&](const Eigen::VectorXd& qq, const Eigen::VectorXd& vv, const Eigen::VectorXd& aa) {
      return model.InverseDynamicsFromCoefficients(w_true, qq, vv, aa);
    };
    auto plant_qdd = [&](const Eigen::VectorXd& qq, const Eigen::VectorXd& vv, const Eigen::VectorXd& tt) {
      return ForwardDynamics(true_robot, qq, vv, tt);
    };
    double sum_sq = 0;
    int count = 0;
    const long steps = static_cast<long>(seconds / dt);
    for (long k = 0; k < steps; ++k) {
      const double t = k * dt;
      const JointTrajectoryPoint ref = reference.Evaluate(t);
      // Computed-torque control with the current estimate (allocation-free features).
      qdd_cmd = ref.qdd + kp * (ref.q - q) + kd * (ref.qd - qd);
      model.Features(q, qd, qdd_cmd, &workspace, A);
      tau.noalias() = A * estimator.coefficients();
      // The plant moves for one tick under that torque (RK4 on the true dynamics).
      q_prev = q;
      qd_prev = qd;
      const Eigen::VectorXd a1 = plant_qdd(q, qd, tau);
      const Eigen::VectorXd a2 = plant_qdd(q + 0.5 * dt * qd, qd + 0.5 * dt * a1, tau);
      const Eigen::VectorXd a3 = plant_qdd(q + 0.5 * dt * (qd + 0.5 * dt * a1), qd + 0.5 * dt * a2, tau);
      const Eigen::VectorXd a4 = plant_qdd(q + dt * (qd + 0.5 * dt * a2), qd + dt * a3, tau);
      q += dt * qd + dt * dt / 6.0 * (a1 + a2 + a3);
      qd += dt / 6.0 * (a1 + 2 * a2 + 2 * a3 + a4);
      // The estimator sees what a real controller measures: positions and velocities, the torque it
      // applied, and the acceleration as the velocity's difference (at the tick's midpoint).
      sample.t = t + 0.5 * dt;
      sample.q = 0.5 * (q + q_prev);
      sample.qd = 0.5 * (qd + qd_prev);
      sample.qdd = (qd - qd_prev) / dt;
      sample.tau = tau;
      if (adapt) {
        estimator.Update(sample);  // the tick: allocation-free
      }
      sum_sq += (ref.q - q_prev).squaredNorm() / n;
      ++count;
      if (count == 50) {
        windows.push_back({std::sqrt(sum_sq / count), estimator.Body(payload).mass()});
        sum_sq = 0;
        count = 0;
      }
    }

    return windows;
  };
  const auto fixed = run(false), adaptive = run(true);
  std::printf("unknown payload: %.3f kg (prior 0.5 kg)\n", true_mass);
  std::printf("time [s]  tracking RMS [rad]: fixed prior  adaptive   estimated payload mass [kg]\n");
  for (size_t w = 0; w < adaptive.size(); ++w) {
    if (w < 10 || (w + 1) % 20 == 0) {
      std::printf("%8.2f  %29.6f  %8.6f   %8.4f\n", 0.05 * (w + 1), fixed[w].first, adaptive[w].first, adaptive[w].second);
    }
  }
  return 0;
}
