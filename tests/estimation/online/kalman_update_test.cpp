// The Kalman measurement update against the closed form: gain K = P H^T (H P H^T + sigma^2 1)^-1,
// step K r, covariance P - K H P (dense normal-equation algebra, independent of the update's
// Cholesky, span products and symmetric downdate), dense and block-triangular H, with forgetting and
// process noise, the variance cap, Huber weighting, the step bound and the outlier gate.
#include "inertial/estimation/online/kalman_update.hpp"
#include "inertial/estimation/online/symmetric_span_product.hpp"

#include <gtest/gtest.h>

#include <Eigen/LU>
#include <limits>
#include <stdexcept>

#include "estimation/synthetic_regression.hpp"
#include "test_support.hpp"

namespace inertial {
namespace {

using testing::RandomMatrix;
using testing::Rng;

constexpr double kInf = std::numeric_limits<double>::infinity();

// Options with every robustness feature off: the plain Kalman update.
KalmanOptions Plain(double sigma) {
  KalmanOptions o;
  o.measurement_sigma = sigma;
  o.huber = o.gate = kInf;
  o.max_step = kInf;
  return o;
}

Eigen::VectorXd RandomStd(Rng& rng, int n) {
  Eigen::VectorXd s(n);
  for (int i = 0; i < n; ++i) s[i] = rng.Uniform(0.5, 2.0);
  return s;
}

// The closed-form update of (x, P) by one sample, with measurement variance sigma2 / weight.
struct Reference {
  Eigen::MatrixXd P;
  Eigen::VectorXd Step(const Eigen::MatrixXd& H, const Eigen::VectorXd& r, double sigma2) {
    const Eigen::MatrixXd S = H * P * H.transpose() + sigma2 * Eigen::MatrixXd::Identity(H.rows(), H.rows());
    const Eigen::MatrixXd K = P * H.transpose() * S.inverse();
    P = P - K * H * P;
    return K * r;
  }
};

// H with the structure of a serial chain's regressor: row i is zero before column i n / m (the
// bodies the joint does not carry), has exact zeros inside its span too, the last row's span ends
// early (its own effect, not the others'), and one row is zero (a joint at a singular state).
Eigen::MatrixXd Staircase(Rng& rng, int m, int n) {
  Eigen::MatrixXd H = RandomMatrix(rng, m, n);
  for (int i = 0; i < m; ++i) {
    H.row(i).head(i * n / m).setZero();
    H(i, (i * n / m + n) / 2) = 0.0;
  }
  H.row(m - 1).tail(n / 4).setZero();
  if (m > 2) H.row(1).setZero();
  return H;
}

template <class Update = KalmanUpdate>
void ExpectClosedForm(int n, int m, unsigned seed, bool staircase = false) {
  Rng rng(seed);
  const double sigma = 0.7;
  const Eigen::VectorXd std0 = RandomStd(rng, n);
  Update k(n, m, std0, Plain(sigma));
  Reference ref{Eigen::MatrixXd(std0.array().square().matrix().asDiagonal())};
  for (int sample = 0; sample < 30; ++sample) {
    const Eigen::MatrixXd H = staircase ? Staircase(rng, m, n) : RandomMatrix(rng, m, n);
    const Eigen::VectorXd r = RandomMatrix(rng, m, 1);
    const Eigen::MatrixXd S = H * ref.P * H.transpose() + sigma * sigma * Eigen::MatrixXd::Identity(m, m);
    const double d2 = r.dot(S.inverse() * r);
    ASSERT_EQ(k.Step(typename Update::MatrixH(H), typename Update::VectorM(r)), UpdateStatus::kAccepted);
    EXPECT_NEAR(k.normalized_innovation(), std::sqrt(d2 / m), 1e-12 * (1 + d2)) << sample;
    const Eigen::VectorXd dx = ref.Step(H, r, sigma * sigma);
    EXPECT_LT((k.step() - dx).norm(), 1e-11 * (1 + dx.norm())) << sample;
    k.Commit();
    EXPECT_LT((k.Covariance() - ref.P).norm(), 1e-11 * ref.P.norm()) << sample;
  }
}

TEST(KalmanUpdate, MatchesTheClosedFormGainAndCovariance) { ExpectClosedForm(7, 3, 1); }

TEST(KalmanUpdate, TheFixedSizeBodyUpdateMatchesTheClosedForm) { ExpectClosedForm<BodyKalmanUpdate>(10, 6, 7); }

// The body's fixed-size update and the dynamic one take the same decisions and steps with every
// option on (forgetting up to the cap, process noise, Huber weighting, the step bound, the gate and
// a change), so the checks above of the dynamic update's options hold for it too.
TEST(KalmanUpdate, TheFixedSizeBodyUpdateEqualsTheDynamicOne) {
  Rng rng(8);
  KalmanOptions o;
  o.measurement_sigma = 0.3;
  o.forgetting = 0.9;
  o.process_noise = 1e-3;
  o.max_variance_factor = 3.0;
  o.huber = 1.5;
  o.gate = 6.0;
  o.max_consecutive_outliers = 2;
  o.max_step = 0.4;
  const Eigen::VectorXd std0 = RandomStd(rng, 10);
  KalmanUpdate dynamic(10, 6, std0, o);
  BodyKalmanUpdate fixed(10, 6, std0, o);
  int outliers = 0, accepted = 0;
  for (int sample = 0; sample < 60; ++sample) {
    const Eigen::MatrixXd H = RandomMatrix(rng, 6, 10);
    const double scale = sample % 20 >= 10 && sample % 20 < 14 ? 30.0 : 1.0;  // a run of outliers: a change
    const Eigen::VectorXd r = scale * RandomMatrix(rng, 6, 1);
    const UpdateStatus a = dynamic.Step(H, r), b = fixed.Step(Matrix6x10(H), Vector6(r));
    ASSERT_EQ(a, b) << sample;
    EXPECT_NEAR(dynamic.normalized_innovation(), fixed.normalized_innovation(), 1e-12 * dynamic.normalized_innovation());
    if (a != UpdateStatus::kAccepted) {
      ++outliers;
      continue;
    }
    ++accepted;
    EXPECT_LT((dynamic.step() - fixed.step()).norm(), 1e-12 * (1 + dynamic.step().norm())) << sample;
    dynamic.Commit(0.7);
    fixed.Commit(0.7);
    EXPECT_LT((dynamic.Covariance() - fixed.Covariance()).norm(), 1e-12 * dynamic.Covariance().norm()) << sample;
  }
  EXPECT_GT(outliers, 0);
  EXPECT_GT(accepted, 40);
  EXPECT_EQ(dynamic.changes_detected(), fixed.changes_detected());
  EXPECT_GT(fixed.changes_detected(), 0u);
}

TEST(KalmanUpdate, MatchesTheClosedFormAtAHumanoidsSizeToo) { ExpectClosedForm(200, 9, 2); }

// The products over each row's span of nonzeros (and groups of measurements with different spans,
// more measurements than one group, sizes that are not whole blocks) give the dense closed form.
TEST(KalmanUpdate, BlockTriangularMeasurementsMatchTheClosedForm) {
  ExpectClosedForm(23, 2 * kSpanBlock + 3, 4, true);
  ExpectClosedForm(61, 7, 5, true);
  ExpectClosedForm(9, 1, 6, true);
}

// P <- P / lambda + q 1 before every sample while below the cap (here far above what is reached).
TEST(KalmanUpdate, ForgettingAndProcessNoisePredictTheCovariance) {
  Rng rng(3);
  const int n = 5, m = 2;
  const double sigma = 0.4, lambda = 0.95, q = 0.01;
  KalmanOptions o = Plain(sigma);
  o.forgetting = lambda;
  o.process_noise = q;
  o.max_variance_factor = 1e6;
  const Eigen::VectorXd std0 = RandomStd(rng, n);
  KalmanUpdate k(n, m, std0, o);
  Reference ref{Eigen::MatrixXd(std0.array().square().matrix().asDiagonal())};
  for (int sample = 0; sample < 40; ++sample) {
    const Eigen::MatrixXd H = RandomMatrix(rng, m, n);
    const Eigen::VectorXd r = RandomMatrix(rng, m, 1);
    ref.P = ref.P / lambda + q * Eigen::MatrixXd::Identity(n, n);
    ASSERT_EQ(k.Step(H, r), UpdateStatus::kAccepted);
    const Eigen::VectorXd dx = ref.Step(H, r, sigma * sigma);
    EXPECT_LT((k.step() - dx).norm(), 1e-10 * (1 + dx.norm())) << sample;
    k.Commit();
    EXPECT_LT((k.Covariance() - ref.P).norm(), 1e-10 * ref.P.norm()) << sample;
  }
}

// A sample refused by the gate (never committed) still forgets: the prediction is applied before
// the next sample and shows in Covariance() meanwhile; a covariance saved at that moment and
// restored into a fresh update continues bit for bit. Dynamic and fixed sizes, block-triangular H.
template <class Update>
void RefusedSamplesStillForget(int n, int m, Eigen::MatrixXd (*make_h)(Rng&, int, int)) {
  Rng rng(31);
  const double sigma = 0.3, lambda = 0.9, q = 0.02;
  KalmanOptions o = Plain(sigma);
  o.forgetting = lambda;
  o.process_noise = q;
  o.max_variance_factor = 1e6;
  o.gate = 50.0;
  const Eigen::VectorXd std0 = RandomStd(rng, n);
  Update k(n, m, std0, o);
  Reference ref{Eigen::MatrixXd(std0.array().square().matrix().asDiagonal())};
  for (int sample = 0; sample < 30; ++sample) {
    const typename Update::MatrixH H = make_h(rng, m, n);
    const bool glitch = sample % 7 == 3;
    const typename Update::VectorM r = RandomMatrix(rng, m, 1) * (glitch ? 1e4 : 1.0);
    ref.P = ref.P / lambda + q * Eigen::MatrixXd::Identity(n, n);
    if (glitch) {
      ASSERT_EQ(k.Step(H, r), UpdateStatus::kOutlier) << sample;
      EXPECT_LT((k.Covariance() - ref.P).norm(), 1e-10 * ref.P.norm()) << sample;
      Update restored(n, m, std0, o);
      ASSERT_TRUE(restored.SetCovariance(k.Covariance()));
      const typename Update::MatrixH H2 = make_h(rng, m, n);
      const typename Update::VectorM r2 = RandomMatrix(rng, m, 1);
      Update original = k;
      ASSERT_EQ(original.Step(H2, r2), UpdateStatus::kAccepted);
      ASSERT_EQ(restored.Step(H2, r2), UpdateStatus::kAccepted);
      EXPECT_EQ(original.step(), restored.step()) << sample;
      original.Commit();
      restored.Commit();
      EXPECT_EQ(original.Covariance(), restored.Covariance()) << sample;
      continue;
    }
    ASSERT_EQ(k.Step(H, r), UpdateStatus::kAccepted) << sample;
    const Eigen::VectorXd dx = ref.Step(H, r, sigma * sigma);
    EXPECT_LT((k.step() - dx).norm(), 1e-10 * (1 + dx.norm())) << sample;
    k.Commit();
    EXPECT_LT((k.Covariance() - ref.P).norm(), 1e-10 * ref.P.norm()) << sample;
  }
}

Eigen::MatrixXd DenseH(Rng& rng, int m, int n) { return RandomMatrix(rng, m, n); }

TEST(KalmanUpdate, RefusedSamplesStillForget) {
  RefusedSamplesStillForget<KalmanUpdate>(13, 5, Staircase);
  RefusedSamplesStillForget<KalmanUpdate>(40, 7, Staircase);
  RefusedSamplesStillForget<BodyKalmanUpdate>(10, 6, DenseH);
}

// A parameter the data never see stops growing once it reaches its cap (initial variance times
// the factor; the last growth may pass it by at most 1 / lambda); one the data see keeps forgetting.
TEST(KalmanUpdate, ForgettingStopsAtTheVarianceCap) {
  KalmanOptions o = Plain(1.0);
  o.forgetting = 0.5;  // doubles the variance per sample below the cap
  o.max_variance_factor = 3.0;  // cap 27 for the unseen one, 3 for the seen one
  KalmanUpdate k(2, 1, Eigen::Vector2d(1.0, 3.0), o);
  const Eigen::MatrixXd H = Eigen::RowVector2d(1.0, 0.0);  // only parameter 0 is measured
  const Eigen::VectorXd r = Eigen::VectorXd::Constant(1, 0.1);
  const double expected_unseen[] = {18.0, 36.0, 36.0, 36.0, 36.0};  // 9 -> 18 -> 36 (past 27), then held
  double p0 = 1.0;
  for (int sample = 0; sample < 5; ++sample) {
    ASSERT_EQ(k.Step(H, r), UpdateStatus::kAccepted);
    k.Commit();
    EXPECT_NEAR(k.Covariance()(1, 1), expected_unseen[sample], 1e-12) << sample;
    // The seen one: doubled (it stays below its cap of 3), then the scalar update p s^2 / (p + s^2).
    const double predicted = 2 * p0;
    p0 = predicted / (predicted + 1.0);
    EXPECT_NEAR(k.Covariance()(0, 0), p0, 1e-15) << sample;
  }
}

// Beyond the Huber threshold the measurement variance is inflated by e / huber, e the sample's
// normalized innovation before weighting.
TEST(KalmanUpdate, HuberWeightingInflatesTheMeasurementVariance) {
  Rng rng(4);
  const int n = 4, m = 3;
  const double sigma = 0.5, huber = 1.5;
  KalmanOptions o = Plain(sigma);
  o.huber = huber;
  const Eigen::VectorXd std0 = RandomStd(rng, n);
  KalmanUpdate k(n, m, std0, o);
  Reference ref{Eigen::MatrixXd(std0.array().square().matrix().asDiagonal())};
  const Eigen::MatrixXd H = RandomMatrix(rng, m, n);
  const Eigen::VectorXd r = 20.0 * RandomMatrix(rng, m, 1);
  const Eigen::MatrixXd S = H * ref.P * H.transpose() + sigma * sigma * Eigen::MatrixXd::Identity(m, m);
  const double e = std::sqrt(r.dot(S.inverse() * r) / m);
  ASSERT_GT(e, huber);
  ASSERT_EQ(k.Step(H, r), UpdateStatus::kAccepted);
  EXPECT_NEAR(k.normalized_innovation(), e, 1e-12 * e);
  const Eigen::VectorXd dx = ref.Step(H, r, sigma * sigma * e / huber);
  EXPECT_LT((k.step() - dx).norm(), 1e-11 * dx.norm());
  k.Commit();
  EXPECT_LT((k.Covariance() - ref.P).norm(), 1e-11 * ref.P.norm());
}

// A step longer than max_step (infinity norm) is shortened along its direction, and the
// covariance takes only that fraction of the information: P - f K H P.
TEST(KalmanUpdate, LongStepsAreShortenedAndTakeTheirShareOfInformation) {
  Rng rng(5);
  const int n = 4, m = 2;
  KalmanOptions o = Plain(0.1);
  o.max_step = 0.05;
  const Eigen::VectorXd std0 = RandomStd(rng, n);
  KalmanUpdate k(n, m, std0, o);
  const Eigen::MatrixXd P = std0.array().square().matrix().asDiagonal();
  const Eigen::MatrixXd H = RandomMatrix(rng, m, n);
  const Eigen::VectorXd r = RandomMatrix(rng, m, 1);
  const Eigen::MatrixXd K = P * H.transpose() * (H * P * H.transpose() + 0.01 * Eigen::MatrixXd::Identity(m, m)).inverse();
  const Eigen::VectorXd full = K * r;
  const double f = 0.05 / full.lpNorm<Eigen::Infinity>();
  ASSERT_LT(f, 1.0);
  ASSERT_EQ(k.Step(H, r), UpdateStatus::kAccepted);
  EXPECT_NEAR(k.step().lpNorm<Eigen::Infinity>(), 0.05, 1e-15);
  EXPECT_LT((k.step() - f * full).norm(), 1e-12);
  k.Commit(0.5);  // and a caller's own fraction on top
  const Eigen::MatrixXd expected = P - 0.5 * f * K * H * P;
  EXPECT_LT((k.Covariance() - expected).norm(), 1e-12 * expected.norm());
}

// Innovations beyond the gate are refused, P untouched; more than max_consecutive_outliers in a
// row are a change: P back to its initial value and the sample taken.
TEST(KalmanUpdate, GateRefusesOutliersUntilARunOfThemIsAChange) {
  KalmanOptions o = Plain(1.0);
  o.gate = 10.0;
  o.max_consecutive_outliers = 2;
  KalmanUpdate k(1, 1, Eigen::VectorXd::Constant(1, 1.0), o);
  const Eigen::MatrixXd H = Eigen::MatrixXd::Constant(1, 1, 1.0);
  for (int i = 0; i < 5; ++i) {  // shrink P to 1/6 with small innovations
    ASSERT_EQ(k.Step(H, Eigen::VectorXd::Constant(1, 0.5)), UpdateStatus::kAccepted);
    k.Commit();
  }
  EXPECT_NEAR(k.Covariance()(0, 0), 1.0 / 6.0, 1e-15);
  const Eigen::VectorXd far = Eigen::VectorXd::Constant(1, 100.0);
  EXPECT_EQ(k.Step(H, far), UpdateStatus::kOutlier);
  EXPECT_NEAR(k.normalized_innovation(), 100.0 / std::sqrt(1.0 / 6.0 + 1.0), 1e-12);
  EXPECT_EQ(k.Step(H, far), UpdateStatus::kOutlier);
  EXPECT_NEAR(k.Covariance()(0, 0), 1.0 / 6.0, 1e-15);
  EXPECT_EQ(k.changes_detected(), 0u);
  ASSERT_EQ(k.Step(H, far), UpdateStatus::kAccepted);  // the third in a row: a change
  EXPECT_EQ(k.changes_detected(), 1u);
  EXPECT_NEAR(k.step()[0], 100.0 * 1.0 / (1.0 + 1.0), 1e-12);  // the gain of P = 1 again
  k.Commit();
  EXPECT_NEAR(k.Covariance()(0, 0), 0.5, 1e-15);
}

TEST(KalmanUpdate, RefusesBadSizesAndOptions) {
  const Eigen::VectorXd one = Eigen::VectorXd::Ones(2);
  EXPECT_THROW(KalmanUpdate(0, 1, Eigen::VectorXd(), {}), std::invalid_argument);
  EXPECT_THROW(KalmanUpdate(2, 0, one, {}), std::invalid_argument);
  EXPECT_THROW(KalmanUpdate(2, 1, Eigen::VectorXd::Ones(3), {}), std::invalid_argument);
  EXPECT_THROW(KalmanUpdate(2, 1, Eigen::Vector2d(1.0, 0.0), {}), std::invalid_argument);
  EXPECT_THROW(KalmanUpdate(2, 1, Eigen::Vector2d(1.0, kInf), {}), std::invalid_argument);
  auto with = [](auto change) {
    KalmanOptions o;
    change(o);
    return o;
  };
  EXPECT_THROW(KalmanUpdate(2, 1, one, with([](KalmanOptions& o) { o.measurement_sigma = 0; })), std::invalid_argument);
  EXPECT_THROW(KalmanUpdate(2, 1, one, with([](KalmanOptions& o) { o.forgetting = 1.5; })), std::invalid_argument);
  EXPECT_THROW(KalmanUpdate(2, 1, one, with([](KalmanOptions& o) { o.forgetting = 0; })), std::invalid_argument);
  EXPECT_THROW(KalmanUpdate(2, 1, one, with([](KalmanOptions& o) { o.process_noise = -1; })), std::invalid_argument);
  EXPECT_THROW(KalmanUpdate(2, 1, one, with([](KalmanOptions& o) { o.gate = 0; })), std::invalid_argument);
  EXPECT_THROW(KalmanUpdate(2, 1, one, with([](KalmanOptions& o) { o.max_step = 0; })), std::invalid_argument);
  KalmanUpdate k(2, 1, one, {});
  EXPECT_FALSE(k.SetCovariance(Eigen::MatrixXd::Identity(3, 3)));
  Eigen::MatrixXd nan = Eigen::MatrixXd::Identity(2, 2);
  nan(0, 1) = std::nan("");
  EXPECT_FALSE(k.SetCovariance(nan));
  EXPECT_EQ(k.Covariance(), Eigen::MatrixXd::Identity(2, 2));
  EXPECT_TRUE(k.SetCovariance(4 * Eigen::MatrixXd::Identity(2, 2)));
  EXPECT_EQ(k.Covariance(), 4 * Eigen::MatrixXd::Identity(2, 2));
}

}  // namespace
}  // namespace inertial
