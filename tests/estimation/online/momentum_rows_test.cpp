#include "inertial/estimation/online/momentum_rows.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include <Eigen/QR>

#include "examples/bundled_robots.hpp"
#include "estimation/leg_chain.hpp"
#include "inertial/signal/causal_acceleration.hpp"
#include "test_support.hpp"

namespace inertial {
namespace {

using testing::Rng;
using examples::Arm7;
using examples::BundledRobot;
using examples::Leg3;

// Sampled at 200 Hz with 20 % jitter: q(t) = a sin(w t + phi), exact torques from the model's
// recursive Newton-Euler. Returns the worst |y - A w| / max|tau| over the rows after the first
// second, for momentum rows and for rows of A(q, qd, qdd) with qdd from the causal
// differentiator at the same cutoff, the way a stream without qdd is handled today.
struct RowErrors {
  double momentum = 0.0;
  double causal_acceleration = 0.0;
};

RowErrors EquationErrors(const RobotDynamics& model, const Eigen::VectorXd& x, double cutoff_hz, Rng& rng) {
  const int n = model.num_dofs();
  Eigen::VectorXd a(n), w(n), phi(n);
  for (int i = 0; i < n; ++i) {
    a[i] = rng.Uniform(0.3, 1.0);
    w[i] = rng.Uniform(1.0, 4.0);
    phi[i] = rng.Uniform(-3, 3);
  }
  const Eigen::VectorXd coefficients = model.Coefficients(x);
  MomentumRows rows(model, cutoff_hz, MomentumRows::Corner::kFixed);
  CausalAcceleration differentiator(n, cutoff_hz);
  Eigen::MatrixXd A(n, model.num_features()), A_causal(n, model.num_features());
  Eigen::VectorXd y(n), qdd_causal(n);
  RowErrors errors;
  double t = 0.0, tau_scale = 0.0;
  for (int k = 0; k < 2000; ++k) {
    t += 0.005 * rng.Uniform(0.8, 1.2);
    const Eigen::VectorXd q = (a.array() * (w.array() * t + phi.array()).sin()).matrix();
    const Eigen::VectorXd qd = (a.array() * w.array() * (w.array() * t + phi.array()).cos()).matrix();
    const Eigen::VectorXd qdd = (-a.array() * w.array().square() * (w.array() * t + phi.array()).sin()).matrix();
    const Eigen::VectorXd tau = model.InverseDynamics(x, q, qd, qdd);
    tau_scale = std::max(tau_scale, tau.cwiseAbs().maxCoeff());
    const bool have_row = rows.Update(model, t, q, qd, tau, A, y);
    const bool have_qdd = differentiator.Update(t, qd, &qdd_causal);
    if (t < 1.0) continue;
    EXPECT_TRUE(have_row && have_qdd);
    errors.momentum = std::max(errors.momentum, (y - A * coefficients).cwiseAbs().maxCoeff());
    model.Features(q, qd, qdd_causal, A_causal);
    errors.causal_acceleration = std::max(errors.causal_acceleration, (tau - A_causal * coefficients).cwiseAbs().maxCoeff());
  }
  errors.momentum /= tau_scale;
  errors.causal_acceleration /= tau_scale;
  return errors;
}

// Momentum rows hold the dynamics to the discretization's O(dt^2) whatever the filter (no lag
// between the sides); rows with a causally differentiated qdd are off by the filter's lag.
TEST(MomentumRows, HoldTheDynamicsWithoutAccelerationAndWithoutLag) {
  Rng rng(3);
  for (const auto& [robot, effects] : {std::pair{Leg3(), std::string("viscous,coulomb:scale=0.2,armature@knee,offset")},
                                       std::pair{Arm7(), std::string("viscous,coulomb:scale=0.2,payload@tool0:mass=2")}}) {
    const RobotDynamics model = robot.Dynamics(effects);
    Eigen::VectorXd x(model.num_parameters());
    for (int i = 0; i < x.size(); ++i) x[i] = rng.Uniform(-0.3, 0.3);
    for (const double cutoff : {2.0, 10.0, 30.0}) {
      SCOPED_TRACE(effects + ", cutoff " + std::to_string(cutoff) + " Hz");
      const RowErrors e = EquationErrors(model, x, cutoff, rng);
      std::cerr << effects << " cutoff " << cutoff << " Hz: worst row error / max |tau|: momentum " << e.momentum
                << ", causal qdd " << e.causal_acceleration << "\n";
      EXPECT_LT(e.momentum, 2e-3);
      EXPECT_LT(10 * e.momentum, e.causal_acceleration);
    }
  }
}

// A least-squares fit of momentum rows (no qdd) predicts a held-out trajectory as well as one of
// rows with the exact qdd: the leg, 20 s at 200 Hz, 0.05 N m of torque noise, both fits the
// minimum-norm least squares of the same coefficients, judged on the exact features of another
// excitation. The filter's cutoff changes how much noise the rows keep, not their truth.
TEST(MomentumRows, FitWithoutAccelerationPredictsAsTheExactOne) {
  using namespace testing;
  Rng rng(8);
  const RobotDynamics truth(LegChain(LegTrueLinks()), kLegJoints, ParseEffectList("viscous"), NoLinks());
  const Eigen::VectorXd x_true = truth.ParametersFromEffectCoefficients(Eigen::Vector3d(0.2, 0.1, 0.3));
  const JointSamples train = ExciteLeg(truth, x_true, 4000, 0.005, 0.05, rng);
  const JointSamples test = ExciteLeg(truth, x_true, 4000, 0.005, 0.0, rng, 1.0);
  const int n = 3, f = truth.num_features();
  Eigen::MatrixXd A_exact(3 * train.size(), f), A_momentum(3 * train.size(), f);
  Eigen::VectorXd y_exact(3 * train.size()), y_momentum(3 * train.size());
  Eigen::MatrixXd A(n, f);
  Eigen::VectorXd y(n);
  for (const double cutoff : {2.0, 5.0, 20.0}) {
    MomentumRows rows(truth, cutoff, MomentumRows::Corner::kFixed);
    int m = 0;
    for (int k = 0; k < train.size(); ++k) {
      truth.Features(train.q.row(k).transpose(), train.qd.row(k).transpose(), train.qdd.row(k).transpose(), A);
      A_exact.middleRows(3 * k, 3) = A;
      y_exact.segment(3 * k, 3) = train.tau.row(k).transpose();
      if (rows.Update(truth, train.t[k], train.q.row(k).transpose(), train.qd.row(k).transpose(), train.tau.row(k).transpose(), A, y)) {
        A_momentum.middleRows(3 * m, 3) = A;
        y_momentum.segment(3 * m, 3) = y;
        ++m;
      }
    }
    const Eigen::VectorXd w_exact = A_exact.completeOrthogonalDecomposition().solve(y_exact);
    const Eigen::VectorXd w_momentum =
        A_momentum.topRows(3 * m).completeOrthogonalDecomposition().solve(y_momentum.head(3 * m));
    double e_exact = 0.0, e_momentum = 0.0;
    for (int k = 0; k < test.size(); ++k) {
      truth.Features(test.q.row(k).transpose(), test.qd.row(k).transpose(), test.qdd.row(k).transpose(), A);
      const Eigen::VectorXd tau = test.tau.row(k).transpose();
      e_exact += (A * w_exact - tau).squaredNorm();
      e_momentum += (A * w_momentum - tau).squaredNorm();
    }
    const double rms_exact = std::sqrt(e_exact / (3.0 * test.size()));
    const double rms_momentum = std::sqrt(e_momentum / (3.0 * test.size()));
    std::cerr << "cutoff " << cutoff << " Hz: held-out RMS, exact qdd " << rms_exact << " N m, momentum rows "
              << rms_momentum << " N m (" << rms_momentum / rms_exact << "x)\n";
    // White torque noise: the filter's smoothing costs information the lower its cutoff (measured
    // 1.13x at 2 Hz, 1.06x at 5 Hz, 1.04x at 20 Hz); no lag bias at any cutoff.
    EXPECT_LT(rms_momentum, (cutoff < 5.0 ? 1.2 : 1.10) * rms_exact) << "cutoff " << cutoff;
  }
}

TEST(MomentumRows, FirstSamplePrimesAndResetForgets) {
  const RobotDynamics model = Leg3().Dynamics("viscous");
  MomentumRows rows(model, 5.0, MomentumRows::Corner::kFixed);
  Eigen::MatrixXd A(3, model.num_features());
  Eigen::VectorXd y(3);
  const Eigen::VectorXd q = Eigen::Vector3d(0.1, 0.2, 0.3), qd = Eigen::Vector3d(0.5, -0.2, 0.1);
  const Eigen::VectorXd tau = Eigen::Vector3d(1, 2, 3);
  EXPECT_FALSE(rows.Update(model, 0.0, q, qd, tau, A, y));
  EXPECT_TRUE(rows.Update(model, 0.01, q, qd, tau, A, y));
  rows.Reset();
  EXPECT_FALSE(rows.primed());
  EXPECT_FALSE(rows.Update(model, 0.02, q, qd, tau, A, y));
  // A step longer than 1 / (2 f_c) = 0.1 s restarts the filters; one just under it does not.
  EXPECT_TRUE(rows.Update(model, 0.119, q, qd, tau, A, y));
  EXPECT_FALSE(rows.Update(model, 0.2191, q, qd, tau, A, y));
  EXPECT_TRUE(rows.primed());
  EXPECT_TRUE(rows.Update(model, 0.23, q, qd, tau, A, y));
  EXPECT_THROW(MomentumRows(model, 0.0), std::invalid_argument);
  EXPECT_THROW(MomentumRows(model, std::nan("")), std::invalid_argument);
}

}  // namespace
}  // namespace inertial
