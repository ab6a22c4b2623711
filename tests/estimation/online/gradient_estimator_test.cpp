// The natural gradient law (gradient_estimator.hpp): one step against its formula computed
// independently (the symmetric square root of J instead of the log-Cholesky factor), the natural
// gradient and the metric against finite differences of the log-det divergence and of the loss,
// consistency of every step, convergence to the least-squares fit of the samples, the Huber
// weights, gate and step bound, a refused sample that changes nothing, a restore bit for bit,
// refusals of bad construction.
#include "inertial/estimation/online/gradient_estimator.hpp"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <stdexcept>

#include "estimation/synthetic_regression.hpp"
#include "inertial/inertia/closed_form_bodies.hpp"
#include "inertial/inertia/consistency.hpp"
#include "inertial/inertia/log_det_divergence.hpp"
#include "test_support.hpp"

namespace inertial {
namespace {

using testing::RandomMatrix;
using testing::Rng;
using testing::Scalars;

// f(J) of a symmetric positive definite J through its eigen-decomposition (exp, sqrt ...).
template <class Fn>
Matrix4 SymmetricFunction(const Matrix4& J, Fn&& f) {
  const Eigen::SelfAdjointEigenSolver<Matrix4> eig(J);
  Vector4 l = eig.eigenvalues();
  for (int i = 0; i < 4; ++i) l[i] = f(l[i]);
  return eig.eigenvectors() * l.asDiagonal() * eig.eigenvectors().transpose();
}

InertialParams Prior() {
  Pose pose;
  pose.p_BoCo_B = Vector3(0.05, -0.02, 0.1);
  return SolidBox(2.0, 0.3, 0.2, 0.1, pose);
}

// One body, one sample: S = A^T A, s = A^T y, g = s - S w; the step J+ = J^1/2 expm(gamma
// J^1/2 T*(g) J^1/2) J^1/2 with gamma = gain (g . dw) / (dw^T S dw), dw = pi(J T*(g) J).
TEST(GradientEstimator, OneStepIsTheNaturalGradientStepOnTheManifold) {
  Rng rng(1);
  const InertialParams prior = Prior();
  GradientOptions o;
  o.huber = o.gate = 1e9;
  o.max_step = 1e9;
  for (int trial = 0; trial < 10; ++trial) {
    const int m = 6;
    GradientEstimator law(ParameterLayout::SingleBody(prior), m, Eigen::VectorXd::Zero(10), Eigen::VectorXd::Ones(10), o);
    const Eigen::MatrixXd A = RandomMatrix(rng, m, 10);
    const Eigen::VectorXd y = A * prior.vector() + 0.3 * RandomMatrix(rng, m, 1);
    ASSERT_EQ(law.Update(0.0, A, y), UpdateStatus::kAccepted);

    const Matrix10 S = A.transpose() * A;
    const Vector10 g = A.transpose() * y - S * prior.vector();
    const Matrix4 J = prior.pseudo_inertia();
    const Matrix4 root = SymmetricFunction(J, [](double l) { return std::sqrt(l); });
    const Matrix4 T = PseudoInertiaGradient(g);
    const Vector10 dw = PiFromPseudoInertia(J * T * J);
    const double gamma = o.gain * g.dot(dw) / dw.dot(S * dw);
    const Matrix4 next = root * SymmetricFunction(gamma * root * T * root, [](double l) { return std::exp(l); }) * root;
    Vector10 w;
    law.Coefficients(w);
    const Vector10 expected = PiFromPseudoInertia(next);
    EXPECT_LT((w - expected).norm(), 1e-11 * expected.norm()) << "trial " << trial;
    EXPECT_TRUE(CheckConsistency(InertialParams::FromVector(w)).fully_consistent());
  }
}

// The second step goes along the conjugate direction d = z2 + beta z1 (Polak-Ribiere+,
// beta = max(0, z2 . (g2 - g1) / (z1 . g1)), 0 where d would not descend, z = pi(J T*(g) J)), with
// the exact line search of the
// second objective along d: J2 = J1^1/2 expm(gamma J1^-1/2 J(d) J1^-1/2) J1^1/2.
TEST(GradientEstimator, SecondStepIsAlongTheConjugateDirection) {
  Rng rng(6);
  const InertialParams prior = Prior();
  GradientOptions o;
  o.huber = o.gate = 1e9;
  o.max_step = 1e9;
  int conjugate = 0;
  for (int trial = 0; trial < 20; ++trial) {
    const int m = 20;
    GradientEstimator law(ParameterLayout::SingleBody(prior), m, Eigen::VectorXd::Zero(10), Eigen::VectorXd::Ones(10), o);
    // The second sample near the first, as consecutive samples of a stream.
    const Eigen::MatrixXd A1 = RandomMatrix(rng, m, 10);
    const Eigen::MatrixXd A2 = A1 + 0.05 * RandomMatrix(rng, m, 10);
    const Eigen::VectorXd y1 = A1 * prior.vector() + 0.01 * RandomMatrix(rng, m, 1);
    const Eigen::VectorXd y2 = A2 * prior.vector() + 0.01 * RandomMatrix(rng, m, 1);
    ASSERT_EQ(law.Update(0.0, A1, y1), UpdateStatus::kAccepted);
    Vector10 w1;
    law.Coefficients(w1);
    ASSERT_EQ(law.Update(1.0, A2, y2), UpdateStatus::kAccepted);
    Vector10 w2;
    law.Coefficients(w2);

    const Matrix10 S1 = A1.transpose() * A1, S2 = S1 + A2.transpose() * A2;
    const Vector10 s1 = A1.transpose() * y1, s2 = s1 + A2.transpose() * y2;
    const Matrix4 J0 = prior.pseudo_inertia(), J1 = PseudoInertiaFromPi(w1);
    const Vector10 g1 = s1 - S1 * prior.vector(), g2 = s2 - S2 * w1;
    const Vector10 z1 = PiFromPseudoInertia(J0 * PseudoInertiaGradient(g1) * J0);
    const Vector10 z2 = PiFromPseudoInertia(J1 * PseudoInertiaGradient(g2) * J1);
    double beta = std::max(0.0, z2.dot(g2 - g1) / z1.dot(g1));
    if (g2.dot(z2 + beta * z1) <= 0) beta = 0.0;  // not a descent direction: restart along z2
    conjugate += beta > 0 ? 1 : 0;
    const Vector10 d = z2 + beta * z1;
    const double gamma = g2.dot(d) / d.dot(S2 * d);
    const Matrix4 root = SymmetricFunction(J1, [](double l) { return std::sqrt(l); });
    const Matrix4 inverse_root = root.inverse();
    const Matrix4 X = inverse_root * PseudoInertiaFromPi(d) * inverse_root;
    const Matrix4 J2 = root * SymmetricFunction(gamma * X, [](double l) { return std::exp(l); }) * root;
    const Vector10 expected = PiFromPseudoInertia(J2);
    EXPECT_LT((w2 - expected).norm(), 1e-10 * expected.norm()) << "trial " << trial << ", beta " << beta;
  }
  EXPECT_GE(conjugate, 3);  // the conjugate case is exercised (4 of the 20 draws), not only restarts
}

// The metric is the Hessian of the divergence (second difference of d(J + eps X || J) along X),
// the natural gradient J (dL/dJ) J represents dL/dJ in it (<N, X>_J = dL/dJ[X], the first
// difference of L along X), and the discrete step leaves J along it: (J+(gamma) - J) / gamma ->
// J T*(g) J = -J (dL/dJ) J.
TEST(GradientEstimator, NaturalGradientAgainstFiniteDifferencesOfTheDivergence) {
  Rng rng(2);
  const InertialParams prior = Prior();
  const Matrix4 J = prior.pseudo_inertia();
  const Matrix4 Ji = J.inverse();
  for (int trial = 0; trial < 10; ++trial) {
    Matrix4 X;
    for (int i = 0; i < 4; ++i) {
      for (int j = i; j < 4; ++j) X(i, j) = X(j, i) = rng.Uniform(-1.0, 1.0) * std::sqrt(J(i, i) * J(j, j));
    }
    const double h = 1e-4;
    const double second = (LogDetDivergence(J + h * X, J) - 2.0 * LogDetDivergence(J, J) + LogDetDivergence(J - h * X, J)) / (h * h);
    const double metric = (Ji * X * Ji * X).trace();
    EXPECT_NEAR(second, metric, 1e-5 * metric) << "trial " << trial;

    const int m = 5;
    const Eigen::MatrixXd A = RandomMatrix(rng, m, 10);
    const Eigen::VectorXd y = RandomMatrix(rng, m, 1);
    const auto loss = [&](const Matrix4& K) { return 0.5 * (y - A * PiFromPseudoInertia(K)).squaredNorm(); };
    const Vector10 g = A.transpose() * (y - A * prior.vector());
    const Matrix4 dL = -PseudoInertiaGradient(g);  // dL/dJ
    const Matrix4 N = J * dL * J;
    const double directional = (loss(J + h * X) - loss(J - h * X)) / (2.0 * h);
    EXPECT_NEAR((Ji * N * Ji * X).trace(), directional, 1e-7 * (1.0 + std::abs(directional))) << "trial " << trial;

    // A step bounded to 1e-4 of J (max_step on |gamma S_b|_F, S_b = F^T T*(g) F, whose norm is that
    // of J^1/2 T*(g) J^1/2 for any factor F): J+ - J = gamma J T*(g) J + O(gamma^2).
    GradientOptions o;
    o.huber = o.gate = 1e9;
    o.max_step = 1e-4;
    GradientEstimator law(ParameterLayout::SingleBody(prior), m, Eigen::VectorXd::Zero(10), Eigen::VectorXd::Ones(10), o);
    ASSERT_EQ(law.Update(0.0, A, y), UpdateStatus::kAccepted);
    Vector10 w;
    law.Coefficients(w);
    const Matrix4 root = SymmetricFunction(J, [](double l) { return std::sqrt(l); });
    const double gamma = o.max_step / (root * PseudoInertiaGradient(g) * root).norm();
    const Matrix4 moved = PseudoInertiaFromPi(w) - J;
    EXPECT_LT((moved + gamma * N).norm(), 1e-3 * (gamma * N).norm()) << "trial " << trial;
  }
}

// Two bodies adding into one block of features (a payload on its link, without features of its
// own): each moves along its own natural gradient J_b T*(g) J_b, and the line search sizes the step
// for their sum; a frozen body stays where it is.
TEST(GradientEstimator, BodiesSharingFeaturesEachTakeTheirOwnStep) {
  Rng rng(7);
  const InertialParams link = Prior();
  Pose pose;
  pose.p_BoCo_B = Vector3(0.0, 0.1, -0.2);
  const InertialParams payload = SolidBox(0.5, 0.05, 0.05, 0.05, pose);
  const ParameterLayout layout(10, {BodyBlock{LogCholeskyParameterization(link), 0, 0}, BodyBlock{LogCholeskyParameterization(payload), 0, 10}}, {});
  GradientOptions o;
  o.huber = o.gate = 1e9;
  o.max_step = 1e9;
  const int m = 6;
  const Eigen::MatrixXd A = RandomMatrix(rng, m, 10);
  const Eigen::VectorXd y = A * (link.vector() + 1.3 * payload.vector()) + 0.01 * RandomMatrix(rng, m, 1);
  GradientEstimator law(layout, m, Eigen::VectorXd::Zero(20), Eigen::VectorXd::Ones(20), o);
  ASSERT_EQ(law.Update(0.0, A, y), UpdateStatus::kAccepted);
  const Matrix10 S = A.transpose() * A;
  const Vector10 g = A.transpose() * y - S * (link.vector() + payload.vector());
  const Matrix4 T = PseudoInertiaGradient(g);
  const Matrix4 J[2] = {link.pseudo_inertia(), payload.pseudo_inertia()};
  const Vector10 dw = PiFromPseudoInertia(J[0] * T * J[0]) + PiFromPseudoInertia(J[1] * T * J[1]);
  const double gamma = g.dot(dw) / dw.dot(S * dw);
  for (int b = 0; b < 2; ++b) {
    const Matrix4 root = SymmetricFunction(J[b], [](double l) { return std::sqrt(l); });
    const Vector10 expected =
        PiFromPseudoInertia(root * SymmetricFunction(gamma * root * T * root, [](double l) { return std::exp(l); }) * root);
    const Vector10 got = layout.Body(b, law.parameters()).vector();
    EXPECT_LT((got - expected).norm(), 1e-11 * expected.norm()) << "body " << b;
  }
  o.frozen_bodies = {true, false};
  GradientEstimator held(layout, m, Eigen::VectorXd::Zero(20), Eigen::VectorXd::Ones(20), o);
  ASSERT_EQ(held.Update(0.0, A, y), UpdateStatus::kAccepted);
  EXPECT_EQ(held.parameters().head(10), Eigen::VectorXd::Zero(10));
  EXPECT_GT(held.parameters().tail(10).norm(), 0.0);
}

// Whatever the data, every estimate is a fully consistent body: measurements a thousand times
// those of any body the prior could be, of random sign.
TEST(GradientEstimator, EveryStepIsAConsistentBody) {
  Rng rng(3);
  const InertialParams prior = Prior();
  GradientEstimator law(ParameterLayout::SingleBody(prior), 6, Eigen::VectorXd::Zero(10), Eigen::VectorXd::Ones(10));
  for (int k = 0; k < 2000; ++k) {
    const Eigen::MatrixXd A = RandomMatrix(rng, 6, 10);
    const Eigen::VectorXd y = 1000.0 * RandomMatrix(rng, 6, 1);
    const UpdateStatus status = law.Update(0.001 * k, A, y);
    ASSERT_TRUE(status == UpdateStatus::kAccepted || status == UpdateStatus::kOutlier || status == UpdateStatus::kNumerical);
    Vector10 w;
    law.Coefficients(w);
    ASSERT_TRUE(CheckConsistency(InertialParams::FromVector(w)).fully_consistent()) << "sample " << k;
  }
}

// The law minimizes the objective of every sample so far: on noisy linear data its estimate
// follows the least-squares solution S^-1 s of the samples themselves (not the truth), and on a
// fixed objective reaches it.
TEST(GradientEstimator, ConvergesToTheLeastSquaresFitOfItsSamples) {
  Rng rng(4);
  const int n = 4, m = 2;
  const Eigen::Vector4d truth(0.4, -0.7, 1.1, 0.2);
  GradientOptions o;
  o.huber = o.gate = 1e9;
  GradientEstimator law(Scalars(n, ScalarMap::kLinear), m, Eigen::VectorXd::Zero(n), Eigen::VectorXd::Ones(n), o);
  Eigen::MatrixXd S = Eigen::MatrixXd::Zero(n, n);
  Eigen::VectorXd s = Eigen::VectorXd::Zero(n);
  for (int k = 0; k < 3000; ++k) {
    const Eigen::MatrixXd A = RandomMatrix(rng, m, n);
    const Eigen::VectorXd y = A * truth + 0.1 * RandomMatrix(rng, m, 1);
    S += A.transpose() * A;
    s += A.transpose() * y;
    ASSERT_EQ(law.Update(0.01 * k, A, y), UpdateStatus::kAccepted);
  }
  const Eigen::VectorXd fit = S.ldlt().solve(s);
  EXPECT_LT((law.parameters() - fit).norm(), 1e-3);  // while the samples come, within their last changes
  // Samples that add nothing (A = 0, y = 0) leave the objective as it is: the law reaches its minimizer.
  for (int k = 0; k < 500; ++k) {
    ASSERT_EQ(law.Update(30.0 + 0.01 * k, Eigen::MatrixXd::Zero(m, n), Eigen::VectorXd::Zero(m)), UpdateStatus::kAccepted);
  }
  EXPECT_LT((law.parameters() - fit).norm(), 1e-12);
  EXPECT_GT((fit - truth).norm(), 1e-4);  // the noise: the fit is not the truth, the law follows the fit
  EXPECT_EQ(law.Covariance().size(), 0);  // the law keeps no covariance
  EXPECT_EQ(law.kind(), "gradient");
}

// A residual beyond `huber` sigmas enters the statistics with weight huber / e; one beyond the
// gate is refused; the step is bounded; a step beyond max_abs_parameter is refused and leaves the
// statistics as they were.
TEST(GradientEstimator, HuberWeightGateStepBoundAndRefusal) {
  GradientOptions o;
  o.measurement_sigma = 1.0;
  o.huber = 2.0;
  o.gate = 50.0;
  o.max_step = 10.0;
  const Eigen::MatrixXd A = Eigen::MatrixXd::Identity(1, 1);
  GradientEstimator law(Scalars(1, ScalarMap::kLinear), 1, Eigen::VectorXd::Zero(1), Eigen::VectorXd::Ones(1), o);
  // r = 8 (e = 8 > 2): weight 1/4, S = 1/4, s = 2, g = 2, dx = 2, gamma = 1 * 4 / (4 / 4) = 4: x = 8.
  ASSERT_EQ(law.Update(0.0, A, Eigen::VectorXd::Constant(1, 8.0)), UpdateStatus::kAccepted);
  EXPECT_DOUBLE_EQ(law.parameters()[0], 8.0);
  EXPECT_DOUBLE_EQ(law.State().statistics(0, 0), 0.25);
  // r = 100 - 8 > gate: refused, nothing changes.
  EXPECT_EQ(law.Update(1.0, A, Eigen::VectorXd::Constant(1, 100.0)), UpdateStatus::kOutlier);
  EXPECT_DOUBLE_EQ(law.parameters()[0], 8.0);
  EXPECT_DOUBLE_EQ(law.State().statistics(0, 0), 0.25);
  o.huber = 1e9;
  o.max_step = 0.25;
  GradientEstimator bounded(Scalars(1, ScalarMap::kLinear), 1, Eigen::VectorXd::Zero(1), Eigen::VectorXd::Ones(1), o);
  ASSERT_EQ(bounded.Update(0.0, A, Eigen::VectorXd::Constant(1, 8.0)), UpdateStatus::kAccepted);  // |dx| = 8: step 1/32
  EXPECT_DOUBLE_EQ(bounded.parameters()[0], 0.25);
  o.max_step = 1e9;
  o.max_abs_parameter = 1.0;
  GradientEstimator limited(Scalars(1, ScalarMap::kLinear), 1, Eigen::VectorXd::Zero(1), Eigen::VectorXd::Ones(1), o);
  EXPECT_EQ(limited.Update(0.0, A, Eigen::VectorXd::Constant(1, 8.0)), UpdateStatus::kNumerical);  // x would be 8
  EXPECT_DOUBLE_EQ(limited.parameters()[0], 0.0);
  EXPECT_EQ(limited.State().statistics(0, 0), 0.0);
  EXPECT_EQ(limited.State().statistics(0, 1), 0.0);
  // From a memory that is not empty: refused, statistics and direction exactly as they were.
  o.max_abs_parameter = 10.0;
  GradientEstimator second(Scalars(1, ScalarMap::kLinear), 1, Eigen::VectorXd::Zero(1), Eigen::VectorXd::Ones(1), o);
  ASSERT_EQ(second.Update(0.0, A, Eigen::VectorXd::Constant(1, 0.3)), UpdateStatus::kAccepted);  // x = 0.3
  const EstimatorState before = second.State();
  EXPECT_EQ(second.Update(1.0, A, Eigen::VectorXd::Constant(1, 40.0)), UpdateStatus::kNumerical);  // x would be 20.15
  EXPECT_EQ(second.State().statistics, before.statistics);
  EXPECT_EQ(second.State().directions, before.directions);
  EXPECT_EQ(second.parameters(), before.x);
}

// More than max_consecutive_outliers outliers in a row are a change of the system: the memory
// starts over with the sample that ends the run, and the law follows the new system.
TEST(GradientEstimator, ARunOfOutliersRestartsTheMemory) {
  GradientOptions o;
  o.measurement_sigma = 0.1;
  o.max_consecutive_outliers = 5;
  o.max_step = 1e9;  // the step to the new memory's minimizer in one
  const Eigen::MatrixXd A = Eigen::MatrixXd::Identity(1, 1);
  GradientEstimator law(Scalars(1, ScalarMap::kLinear), 1, Eigen::VectorXd::Zero(1), Eigen::VectorXd::Ones(1), o);
  for (int k = 0; k < 100; ++k) ASSERT_EQ(law.Update(0.01 * k, A, Eigen::VectorXd::Constant(1, 1.0)), UpdateStatus::kAccepted);
  EXPECT_NEAR(law.parameters()[0], 1.0, 1e-12);
  for (int k = 0; k < 5; ++k) {
    EXPECT_EQ(law.Update(1.0 + 0.01 * k, A, Eigen::VectorXd::Constant(1, 10.0)), UpdateStatus::kOutlier);
  }
  EXPECT_EQ(law.changes_detected(), 0u);
  // The sixth: a change. Residual 9 = 90 sigmas, Huber weight 3 / 90: S = 1/30, s = 1/3.
  EXPECT_EQ(law.Update(1.1, A, Eigen::VectorXd::Constant(1, 10.0)), UpdateStatus::kAccepted);
  EXPECT_EQ(law.changes_detected(), 1u);
  EXPECT_NEAR(law.State().statistics(0, 0), 1.0 / 30.0, 1e-15);
  EXPECT_NEAR(law.parameters()[0], 10.0, 1e-12);  // the minimizer of the new memory
}

// State() carries x and the statistics: a restored law continues exactly as the original.
TEST(GradientEstimator, RestoreContinuesBitForBit) {
  Rng rng(5);
  const InertialParams prior = Prior();
  const ParameterLayout layout = ParameterLayout::SingleBody(prior);
  GradientEstimator a(layout, 6, Eigen::VectorXd::Zero(10), Eigen::VectorXd::Ones(10));
  std::vector<Eigen::MatrixXd> As;
  std::vector<Eigen::VectorXd> ys;
  for (int k = 0; k < 400; ++k) {
    As.push_back(RandomMatrix(rng, 6, 10));
    ys.push_back(As.back() * prior.vector() + 0.1 * RandomMatrix(rng, 6, 1));
  }
  for (int k = 0; k < 200; ++k) a.Update(0.01 * k, As[k], ys[k]);
  GradientEstimator b(layout, 6, Eigen::VectorXd::Zero(10), Eigen::VectorXd::Ones(10));
  std::string why;
  ASSERT_TRUE(b.Restore(a.State(), &why)) << why;
  for (int k = 200; k < 400; ++k) {
    a.Update(0.01 * k, As[k], ys[k]);
    b.Update(0.01 * k, As[k], ys[k]);
  }
  EXPECT_EQ(a.parameters(), b.parameters());
  EXPECT_EQ(a.State().statistics, b.State().statistics);
  // Statistics of another size are refused, the law untouched.
  EstimatorState wrong = a.State();
  wrong.statistics = Eigen::MatrixXd::Zero(3, 3);
  EXPECT_FALSE(b.Restore(wrong, &why));
  EXPECT_NE(why.find("statistics"), std::string::npos) << why;
  EXPECT_EQ(a.parameters(), b.parameters());
}

TEST(GradientEstimator, RefusesBadConstruction) {
  const ParameterLayout layout = Scalars(2, ScalarMap::kLinear);
  EXPECT_THROW(GradientEstimator(layout, 1, Eigen::VectorXd::Zero(3), Eigen::VectorXd::Ones(2)), std::invalid_argument);
  EXPECT_THROW(GradientEstimator(layout, 1, Eigen::VectorXd::Zero(2), Eigen::Vector2d(1.0, 0.0)), std::invalid_argument);
  EXPECT_THROW(GradientEstimator(layout, 1, Eigen::Vector2d(std::nan(""), 0.0), Eigen::VectorXd::Ones(2)), std::invalid_argument);
  GradientOptions o;
  o.gain = 2.5;
  EXPECT_THROW(GradientEstimator(layout, 1, Eigen::VectorXd::Zero(2), Eigen::VectorXd::Ones(2), o), std::invalid_argument);
}

}  // namespace
}  // namespace inertial
