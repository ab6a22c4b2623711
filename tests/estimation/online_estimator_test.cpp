// Online estimators on single-body streams (a payload on a force/torque sensor): the parameter
// layout's Jacobian against central differences, linear RLS against the batch regularized least
// squares it must equal, recursive Gauss-Newton and the gradient law converging to the true body
// with every tick fully consistent, a payload change re-converged with forgetting, fault injection
// (NaN/Inf, repeated and out-of-order time, 100x outlier bursts, dropped samples), and state
// save/restore continuing identically.
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <cmath>
#include <limits>

#include "inertial/estimation/online_body_estimator.hpp"
#include "inertial/inertia/closed_form_bodies.hpp"
#include "inertial/inertia/consistency.hpp"
#include "inertial/model/rigid_body_regressor.hpp"
#include "inertial/model/robot_dynamics.hpp"
#include "inertial/model/spatial_algebra.hpp"
#include "leg_chain.hpp"
#include "test_support.hpp"

namespace inertial {
namespace {

using testing::Rng;

// The truth: a 1.3 kg box, 0.2 x 0.1 x 0.05 m, rotated, its centre 8 cm from the sensor frame.
InertialParams TrueBody() {
  Pose pose;
  pose.R_BC = Eigen::AngleAxisd(0.4, Vector3(1, 2, 3).normalized()).toRotationMatrix();
  pose.p_BoCo_B = Vector3(0.05, -0.03, 0.06);
  return SolidBox(1.3, 0.2, 0.1, 0.05, pose);
}

// The prior the estimators start from: a 1 kg sphere of radius 5 cm at the origin.
InertialParams Prior() { return SolidSphere(1.0, 0.05); }

// A stream at `rate` Hz: the sensor frame moves with a multi-sine twist (rad/s, m/s), gravity
// rotates in the body frame; the wrench w = Y(xi, xi_dot, g) pi_true exactly, plus Gaussian noise.
std::vector<BodySample> Stream(const InertialParams& body, double seconds, double rate, double sigma, unsigned seed,
                               double t0 = 0.0) {
  Rng rng(seed);
  std::vector<BodySample> out;
  const int N = static_cast<int>(seconds * rate);
  for (int k = 0; k < N; ++k) {
    const double t = t0 + k / rate;
    BodySample s;
    s.t = t;
    for (int i = 0; i < 6; ++i) {
      const double f = 0.3 + 0.17 * i;
      s.twist[i] = (i < 3 ? 2.0 : 0.5) * std::sin(2 * M_PI * f * t + i);
      s.acceleration[i] = (i < 3 ? 2.0 : 0.5) * 2 * M_PI * f * std::cos(2 * M_PI * f * t + i);
    }
    s.has_acceleration = true;
    s.gravity = 9.81 * Vector3(std::sin(0.7 * t), std::cos(0.7 * t) * std::sin(0.3 * t), -std::cos(0.3 * t)).normalized();
    s.wrench = RigidBodyRegressor(s.twist, s.acceleration, s.gravity) * body.vector();
    for (int i = 0; i < 6; ++i) s.wrench[i] += rng.Normal(sigma);
    out.push_back(s);
  }
  return out;
}

double RelativeBodyError(const InertialParams& a, const InertialParams& b) {
  return (a.vector() - b.vector()).norm() / b.vector().norm();
}

OnlineEstimatorOptions Options(EstimatorKind kind, double sigma) {
  OnlineEstimatorOptions o;
  o.kind = kind;
  o.measurement_sigma = sigma;
  o.theta_std = 1.0;
  return o;
}

TEST(ParameterLayout, JacobianMatchesCentralDifferences) {
  Rng rng(31);
  const InertialParams p1 = SolidBox(2.0, 0.3, 0.2, 0.1), p2 = SolidSphere(0.5, 0.05);
  // Two bodies on one feature block (a link and its payload), an offset, an exp coefficient, a spring.
  const ParameterLayout layout(25, {BodyBlock{LogCholeskyParameterization(p1), 0, 0}, BodyBlock{LogCholeskyParameterization(p2), 0, 10}},
                               {ScalarBlock{ScalarMap::kLinear, 20, 20}, ScalarBlock{ScalarMap::kExponential, 21, 21},
                                ScalarBlock{ScalarMap::kSpring, 22, 22}});
  ASSERT_EQ(layout.num_parameters(), 24);
  for (int trial = 0; trial < 20; ++trial) {
    Eigen::MatrixXd A(4, 25);
    for (int i = 0; i < A.size(); ++i) A.data()[i] = rng.Normal();
    Eigen::VectorXd x(24);
    for (int i = 0; i < 24; ++i) x[i] = rng.Uniform(-1, 1);
    Eigen::VectorXd w(25);
    Eigen::MatrixXd H(4, 24);
    layout.Evaluate(x, A, w, H);
    Eigen::VectorXd w2(25);
    layout.Coefficients(x, w2);
    EXPECT_LT((w - w2).norm(), 1e-14);
    EXPECT_LT((w.head<10>() - layout.Body(0, x).vector() - layout.Body(1, x).vector()).norm(), 1e-12);
    Eigen::MatrixXd H_fd(4, 24);
    const double h = 1e-6;
    for (int j = 0; j < 24; ++j) {
      Eigen::VectorXd xp = x, xm = x, wp(25), wm(25);
      xp[j] += h;
      xm[j] -= h;
      layout.Coefficients(xp, wp);
      layout.Coefficients(xm, wm);
      H_fd.col(j) = A * (wp - wm) / (2 * h);
    }
    EXPECT_LT((H - H_fd).norm() / H_fd.norm(), 1e-7);
  }
  EXPECT_THROW(ParameterLayout(10, {BodyBlock{LogCholeskyParameterization(p1), 5, 0}}, {}), std::invalid_argument);
  EXPECT_THROW(ParameterLayout(12, {BodyBlock{LogCholeskyParameterization(p1), 0, 0}}, {ScalarBlock{ScalarMap::kLinear, 10, 9}}),
               std::invalid_argument);
}

// The online estimators' layout of a robot holds every effect kind as RobotDynamics does (the
// asymmetric friction's two levels both e^s, the sigmoid's level e^s): same w(x), and H = A J_w
// against central differences.
TEST(ParameterLayout, FromRobotMatchesTheModelForEveryEffectKind) {
  Rng rng(32);
  const RobotDynamics model(testing::LegChain(testing::LegPriorLinks()), testing::kLegJoints,
                            ParseEffectList("viscous,coulomb,offset@abad,armature@knee,spring@hip,asymmetric@hip,"
                                            "sigmoid@knee:steepness=30:shift=0.01"),
                            testing::NoLinks());
  const ParameterLayout layout = ParameterLayout::FromRobot(model);
  ASSERT_EQ(layout.num_parameters(), model.num_parameters());
  const int P = model.num_parameters(), F = model.num_features();
  for (int trial = 0; trial < 10; ++trial) {
    Eigen::VectorXd x(P);
    for (int i = 0; i < P; ++i) x[i] = rng.Uniform(-0.5, 0.5);
    Eigen::VectorXd w(F);
    layout.Coefficients(x, w);
    EXPECT_LT((w - model.Coefficients(x)).norm(), 1e-13 * (1 + w.norm()));
    Eigen::MatrixXd A(3, F);
    for (int i = 0; i < A.size(); ++i) A.data()[i] = rng.Normal();
    Eigen::MatrixXd H(3, P);
    layout.Evaluate(x, A, w, H);
    Eigen::MatrixXd H_fd(3, P);
    const double h = 1e-6;
    for (int j = 0; j < P; ++j) {
      Eigen::VectorXd xp = x, xm = x;
      xp[j] += h;
      xm[j] -= h;
      H_fd.col(j) = A * (model.Coefficients(xp) - model.Coefficients(xm)) / (2 * h);
    }
    EXPECT_LT((H - H_fd).norm() / H_fd.norm(), 1e-7);
  }
}

// With no forgetting and no robust weighting, recursive least squares is exactly the batch
// regularized least squares: w = (P0^-1 + A^T A / s^2)^-1 (P0^-1 w0 + A^T y / s^2).
TEST(LinearRls, EqualsBatchRegularizedLeastSquares) {
  Rng rng(32);
  const int n = 10, m = 6, N = 300;
  const double sigma = 0.3;
  Eigen::VectorXd w0(n), std0(n), truth(n);
  for (int i = 0; i < n; ++i) {
    w0[i] = rng.Normal();
    std0[i] = rng.Uniform(0.5, 2.0);
    truth[i] = rng.Normal(3.0);
  }
  KalmanOptions o;
  o.measurement_sigma = sigma;
  o.huber = o.gate = std::numeric_limits<double>::infinity();
  o.max_step = std::numeric_limits<double>::infinity();
  LinearRls rls(m, w0, std0, o);
  Eigen::MatrixXd normal = std0.array().square().inverse().matrix().asDiagonal();
  Eigen::VectorXd rhs = normal * w0;
  for (int k = 0; k < N; ++k) {
    Eigen::MatrixXd A(m, n);
    for (int i = 0; i < A.size(); ++i) A.data()[i] = rng.Normal();
    Eigen::VectorXd y = A * truth;
    for (int i = 0; i < m; ++i) y[i] += rng.Normal(sigma);
    ASSERT_EQ(rls.Update(0.01 * k, A, y), UpdateStatus::kAccepted);
    normal += A.transpose() * A / (sigma * sigma);
    rhs += A.transpose() * y / (sigma * sigma);
  }
  const Eigen::VectorXd batch = normal.ldlt().solve(rhs);
  EXPECT_LT((rls.parameters() - batch).norm() / batch.norm(), 1e-10);
  EXPECT_LT((rls.Covariance() - Eigen::MatrixXd(normal.inverse())).norm() / normal.inverse().norm(), 1e-9);
}

// Recursive Gauss-Newton from a wrong prior converges to the true body: after 20 s at 200 Hz with
// wrench noise 0.05 the relative error of pi is below 1 %, and every tick's body is fully
// consistent. The error bound: the batch least-squares error at this noise and excitation is of
// order sigma / (|Y| sqrt(N)) ~ 1e-3 relative; 1 % leaves room for the early nonlinear transient.
TEST(OnlineBodyEstimator, GaussNewtonConvergesWithEveryTickConsistent) {
  const InertialParams truth = TrueBody();
  OnlineBodyEstimator est(Prior(), Options(EstimatorKind::kGaussNewton, 0.05));
  int inconsistent = 0;
  for (const BodySample& s : Stream(truth, 20.0, 200.0, 0.05, 1)) {
    ASSERT_EQ(est.Update(s), UpdateStatus::kAccepted);
    inconsistent += !IsPhysicallyConsistent(est.Body());
  }
  EXPECT_EQ(inconsistent, 0);
  EXPECT_LT(RelativeBodyError(est.Body(), truth), 0.01) << est.Body().vector().transpose();
  // The covariance is meaningful: against the Bayesian Cramer-Rao bound of the whole stream at the
  // truth, (sum H^T H / sigma^2 + P0^-1)^-1 with H = A J_pi_theta at the true theta: no standard
  // deviation of theta above 1.5 times the bound's, none below 0.2 times. An extended Kalman
  // filter's covariance is optimistic after a transient: the information of its early samples was
  // taken with Jacobians far from the truth (here the smallest ratio is 0.25, for one direction;
  // most are 0.5 to 1). And the error of pi within 5 of its standard deviations, entry by entry
  // (4.3 is the largest seen).
  const LogCholeskyParameterization map(Prior());
  const Vector10 theta_true = map.ThetaOf(truth);
  Matrix10 information = Matrix10::Zero();
  for (const BodySample& s : Stream(truth, 20.0, 200.0, 0.05, 1)) {
    Matrix10 J;
    map.ToPi(theta_true, &J);
    const Matrix6x10 H = RigidBodyRegressor(s.twist, s.acceleration, s.gravity) * J;
    information += H.transpose() * H / (0.05 * 0.05);
  }
  const Matrix10 crb = (information + Matrix10::Identity() / (1.0 * 1.0)).inverse();  // with the prior, theta_std 1
  const Eigen::MatrixXd P = est.estimator().Covariance();
  for (int i = 0; i < 10; ++i) {
    const double ratio = std::sqrt(P(i, i) / crb(i, i));
    EXPECT_GT(ratio, 0.2) << i;
    EXPECT_LT(ratio, 1.5) << i;
  }
  const Matrix10 cov = est.layout().BodyCovariance(0, est.estimator().parameters(), P);
  for (int i = 0; i < 10; ++i) {
    EXPECT_LT(std::abs(est.Body().vector()[i] - truth.vector()[i]), 5 * std::sqrt(cov(i, i))) << i;
  }
}

// The COM's standard deviation through its Jacobian, against a Monte Carlo of c = h / m over
// Gaussian pi with the same covariance (an independent, derivative-free reference).
TEST(BodyUncertainty, ComStandardDeviationMatchesMonteCarlo) {
  const InertialParams body = TrueBody();
  Matrix10 L = Matrix10::Zero();
  Rng rng(41);
  for (int i = 0; i < 10; ++i) {
    for (int j = 0; j <= i; ++j) L(i, j) = rng.Normal(i == j ? 1e-3 : 3e-4);
  }
  const Matrix10 C = L * L.transpose();
  const BodyUncertainty u = UncertaintyOf(body, C);
  EXPECT_DOUBLE_EQ(u.mass, std::sqrt(C(0, 0)));
  Vector3 sum = Vector3::Zero(), sum_sq = Vector3::Zero();
  const int N = 200000;
  for (int k = 0; k < N; ++k) {
    Vector10 z;
    for (int i = 0; i < 10; ++i) z[i] = rng.Normal();
    const Vector10 pi = body.vector() + L * z;
    const Vector3 c = pi.segment<3>(1) / pi[0];
    sum += c;
    sum_sq += c.cwiseProduct(c);
  }
  const Vector3 mean = sum / N;
  const Vector3 sd = (sum_sq / N - mean.cwiseProduct(mean)).cwiseSqrt();
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(u.com[i], sd[i], 0.02 * sd[i]) << i;
}

TEST(OnlineBodyEstimator, GaussNewtonFromTwistPairsMidpointRule) {
  const InertialParams truth = TrueBody();
  OnlineBodyEstimator est(Prior(), Options(EstimatorKind::kGaussNewton, 0.05));
  std::vector<BodySample> stream = Stream(truth, 20.0, 500.0, 0.02, 2);
  int buffered = 0;
  for (BodySample s : stream) {
    s.has_acceleration = false;
    const UpdateStatus st = est.Update(s);
    buffered += st == UpdateStatus::kBuffered;
    ASSERT_TRUE(st == UpdateStatus::kAccepted || st == UpdateStatus::kBuffered);
    ASSERT_TRUE(IsPhysicallyConsistent(est.Body()));
  }
  EXPECT_EQ(buffered, 1);
  // The midpoint rule's discretization error is O(dt^2) of the accelerations: 2 % at 500 Hz.
  EXPECT_LT(RelativeBodyError(est.Body(), truth), 0.02);
}

TEST(OnlineBodyEstimator, GradientLawConverges) {
  const InertialParams truth = TrueBody();
  OnlineEstimatorOptions o = Options(EstimatorKind::kGradient, 0.05);
  o.gradient.gain = 1.0;  // the noise is small here (0.05 N against wrenches of ~10 N)
  OnlineBodyEstimator est(Prior(), o);
  const double start = RelativeBodyError(est.Body(), truth);
  for (const BodySample& s : Stream(truth, 60.0, 200.0, 0.05, 3)) {
    ASSERT_EQ(est.Update(s), UpdateStatus::kAccepted);
    ASSERT_TRUE(IsPhysicallyConsistent(est.Body()));
  }
  // A first-order law converges slowly along the weakly excited directions: a tenth of the start.
  EXPECT_LT(RelativeBodyError(est.Body(), truth), 0.1 * start) << start;
}

// Linear RLS on the same stream reaches the truth too, but from a poorly excited start its early
// bodies are not physical; the log-Cholesky estimators never are.
TEST(OnlineBodyEstimator, LinearRlsPassesThroughImpossibleBodies) {
  const InertialParams truth = TrueBody();
  OnlineBodyEstimator lin(Prior(), Options(EstimatorKind::kLinearRls, 0.5));
  int impossible = 0;
  for (const BodySample& s : Stream(truth, 5.0, 200.0, 0.5, 4)) {
    lin.Update(s);
    impossible += !IsPhysicallyConsistent(lin.Body());
  }
  EXPECT_GT(impossible, 0);
}

// A payload picked up at t = 10 s (the body gains a 0.8 kg block 10 cm out): with forgetting
// (lambda = 0.995 per sample at 200 Hz, a memory of about 1 s) the estimate re-converges to the
// new body within 3 s: pi within 3 % from t = 13 s on.
TEST(OnlineBodyEstimator, PayloadChangeReconvergesWithForgetting) {
  const InertialParams before = TrueBody();
  const InertialParams after = before + SolidBox(0.8, 0.05, 0.05, 0.05, Pose{Matrix3::Identity(), Vector3(0.1, 0, 0)});
  OnlineEstimatorOptions o = Options(EstimatorKind::kGaussNewton, 0.05);
  o.kalman.forgetting = 0.995;
  OnlineBodyEstimator est(Prior(), o);
  std::vector<BodySample> stream = Stream(before, 10.0, 200.0, 0.05, 5);
  const std::vector<BodySample> second = Stream(after, 10.0, 200.0, 0.05, 6, 10.0);
  stream.insert(stream.end(), second.begin(), second.end());
  double worst_after_13 = 0;
  for (const BodySample& s : stream) {
    est.Update(s);
    ASSERT_TRUE(IsPhysicallyConsistent(est.Body())) << s.t << ": " << CheckConsistency(est.Body()).reason;
    if (std::abs(s.t - 9.995) < 1e-9) {
      EXPECT_LT(RelativeBodyError(est.Body(), before), 0.03);
    }
    if (s.t >= 13.0) worst_after_13 = std::max(worst_after_13, RelativeBodyError(est.Body(), after));
  }
  EXPECT_LT(worst_after_13, 0.03);
}

// Faults: NaN and Inf in every field, repeated and out-of-order time stamps, a burst of 40
// outliers at 100x the noise, 200 dropped samples. Every fault is rejected and counted, the
// estimate stays finite and consistent at every tick and ends as close to the truth as a clean run.
TEST(OnlineBodyEstimator, FaultsAreRejectedAndTheEstimateRecovers) {
  const InertialParams truth = TrueBody();
  const double sigma = 0.05;
  const std::vector<BodySample> clean = Stream(truth, 20.0, 200.0, sigma, 7);
  OnlineBodyEstimator reference(Prior(), Options(EstimatorKind::kGaussNewton, sigma));
  for (const BodySample& s : clean) reference.Update(s);

  OnlineBodyEstimator est(Prior(), Options(EstimatorKind::kGaussNewton, sigma));
  Rng rng(8);
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  int expected_non_finite = 0, expected_out_of_order = 0;
  for (int k = 0; k < static_cast<int>(clean.size()); ++k) {
    if (k >= 1000 && k < 1200) continue;  // dropped
    BodySample s = clean[k];
    if (k % 97 == 5) {
      BodySample bad = s;
      switch ((k / 97) % 5) {
        case 0: bad.wrench[2] = nan; break;
        case 1: bad.twist[4] = inf; break;
        case 2: bad.acceleration[0] = -inf; break;
        case 3: bad.gravity[1] = nan; break;
        case 4: bad.t = nan; break;
      }
      const Vector10 x_before = est.estimator().parameters();
      EXPECT_EQ(est.Update(bad), UpdateStatus::kNonFinite);
      EXPECT_EQ(est.estimator().parameters(), x_before);
      ++expected_non_finite;
    }
    if (k % 101 == 7 && k > 0) {
      BodySample old = clean[k - 1];  // repeated, then older
      EXPECT_EQ(est.Update(old), UpdateStatus::kOutOfOrder);
      old.t -= 0.5;
      EXPECT_EQ(est.Update(old), UpdateStatus::kOutOfOrder);
      expected_out_of_order += 2;
    }
    if (k >= 2000 && k < 2040) {
      for (int i = 0; i < 6; ++i) s.wrench[i] += 100 * sigma * (rng.Uniform(0, 1) < 0.5 ? -1 : 1) * rng.Uniform(0.5, 1.5);
    }
    est.Update(s);
    ASSERT_TRUE(est.estimator().parameters().allFinite());
    ASSERT_TRUE(IsPhysicallyConsistent(est.Body()));
  }
  const UpdateCounters& c = est.estimator().counters();
  EXPECT_EQ(c[UpdateStatus::kNonFinite], static_cast<std::uint64_t>(expected_non_finite));
  EXPECT_EQ(c[UpdateStatus::kOutOfOrder], static_cast<std::uint64_t>(expected_out_of_order));
  EXPECT_GE(c[UpdateStatus::kOutlier], 30u);  // most of the burst gated out, the rest down-weighted
  const double clean_error = RelativeBodyError(reference.Body(), truth);
  const double faulty_error = RelativeBodyError(est.Body(), truth);
  EXPECT_LT(faulty_error, 2.0 * clean_error + 2e-3) << clean_error;
}

TEST(OnlineBodyEstimator, WrongSizesAreRejectedWithoutThrowing) {
  LinearRls rls(6, Eigen::VectorXd::Zero(10), Eigen::VectorXd::Ones(10));
  EXPECT_EQ(rls.Update(0.0, Eigen::MatrixXd::Zero(5, 10), Eigen::VectorXd::Zero(6)), UpdateStatus::kWrongSize);
  EXPECT_EQ(rls.Update(0.0, Eigen::MatrixXd::Zero(6, 10), Eigen::VectorXd::Zero(7)), UpdateStatus::kWrongSize);
  EXPECT_EQ(rls.counters().rejected(), 2u);
  EXPECT_EQ(rls.parameters(), Eigen::VectorXd::Zero(10));
}

// Save after 10 s, restore into a fresh estimator, continue both: identical estimates.
TEST(OnlineBodyEstimator, StateRestoreContinuesIdentically) {
  for (EstimatorKind kind : {EstimatorKind::kGaussNewton, EstimatorKind::kGradient, EstimatorKind::kLinearRls}) {
    const std::vector<BodySample> stream = Stream(TrueBody(), 20.0, 100.0, 0.05, 9);
    OnlineBodyEstimator a(Prior(), Options(kind, 0.05));
    for (int k = 0; k < 1000; ++k) a.Update(stream[k]);
    const EstimatorState saved = a.estimator().State();
    OnlineBodyEstimator b(Prior(), Options(kind, 0.05));
    std::string why;
    ASSERT_TRUE(b.estimator().Restore(saved, &why)) << why;
    EXPECT_EQ(b.estimator().counters().accepted(), a.estimator().counters().accepted());
    EXPECT_GT(b.estimator().counters().accepted(), 900u);
    // Time continues: a sample from before the checkpoint is out of order for the restored one.
    EXPECT_EQ(b.Update(stream[500]), UpdateStatus::kOutOfOrder);
    for (int k = 1000; k < 2000; ++k) {
      a.Update(stream[k]);
      b.Update(stream[k]);
    }
    EXPECT_EQ(a.estimator().parameters(), b.estimator().parameters()) << ToString(kind);
  }
  // A state of another kind or size is refused, nothing changed.
  OnlineBodyEstimator gn(Prior(), Options(EstimatorKind::kGaussNewton, 0.05));
  OnlineBodyEstimator gr(Prior(), Options(EstimatorKind::kGradient, 0.05));
  std::string why;
  EXPECT_FALSE(gn.estimator().Restore(gr.estimator().State(), &why));
  EXPECT_NE(why.find("gradient"), std::string::npos) << why;
  EstimatorState wrong = gn.estimator().State();
  wrong.x.resize(9);
  EXPECT_FALSE(gn.estimator().Restore(wrong, &why));
}

}  // namespace
}  // namespace inertial
