#include "inertial/signal/savitzky_golay.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cstdio>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "test_support.hpp"

namespace inertial {
namespace {

using testing::Rng;

Eigen::VectorXd UniformTimes(int n, double dt, double t0) {
  Eigen::VectorXd t(n);
  for (int i = 0; i < n; ++i) t[i] = t0 + dt * i;
  return t;
}

/// Steps drawn uniformly in [dt (1 - jitter), dt (1 + jitter)].
Eigen::VectorXd JitteredTimes(int n, double dt, double jitter, double t0, Rng& rng) {
  Eigen::VectorXd t(n);
  t[0] = t0;
  for (int i = 1; i < n; ++i) t[i] = t[i - 1] + dt * rng.Uniform(1.0 - jitter, 1.0 + jitter);
  return t;
}

/// A polynomial sum_k c_k (t - t_ref)^k with its analytic first and second derivatives.
struct Polynomial {
  std::vector<double> c;
  double t_ref = 0.0;
  double Value(double t) const {
    double v = 0.0, p = 1.0;
    for (double ck : c) v += ck * p, p *= (t - t_ref);
    return v;
  }
  double First(double t) const {
    double v = 0.0, p = 1.0;
    for (std::size_t k = 1; k < c.size(); ++k) v += static_cast<double>(k) * c[k] * p, p *= (t - t_ref);
    return v;
  }
  double Second(double t) const {
    double v = 0.0, p = 1.0;
    for (std::size_t k = 2; k < c.size(); ++k) v += static_cast<double>(k * (k - 1)) * c[k] * p, p *= (t - t_ref);
    return v;
  }
};

/// Random polynomials of degrees 0..degree, one per column, with coefficients scaled so that every
/// term stays O(1) over a span of about `span` seconds.
std::vector<Polynomial> RandomPolynomials(int degree, double t_ref, double span, Rng& rng) {
  std::vector<Polynomial> polys;
  for (int d = 0; d <= degree; ++d) {
    Polynomial p;
    p.t_ref = t_ref;
    for (int k = 0; k <= d; ++k) p.c.push_back(rng.Uniform(-2.0, 2.0) / std::pow(span, k));
    polys.push_back(p);
  }
  return polys;
}

void ExpectExactForPolynomials(const Eigen::VectorXd& t, const std::vector<Polynomial>& polys, const SavitzkyGolayOptions& options) {
  const int N = static_cast<int>(t.size());
  const int m = static_cast<int>(polys.size());
  Eigen::MatrixXd x(N, m), d1(N, m), d2(N, m);
  for (int i = 0; i < N; ++i) {
    for (int j = 0; j < m; ++j) {
      x(i, j) = polys[j].Value(t[i]);
      d1(i, j) = polys[j].First(t[i]);
      d2(i, j) = polys[j].Second(t[i]);
    }
  }
  const SavitzkyGolayResult r = SavitzkyGolay(t, x, options);
  ASSERT_EQ(r.value.rows(), N);
  ASSERT_EQ(r.value.cols(), m);
  // Relative to the signal's scale (RelativeError divides by max(1, max |reference|)).
  EXPECT_LT(testing::RelativeError(r.value, x), 1e-9);
  EXPECT_LT(testing::RelativeError(r.first, d1), 1e-9);
  EXPECT_LT(testing::RelativeError(r.second, d2), 1e-9);
}

TEST(SavitzkyGolay, ExactForPolynomialsUpToOrderOnUniformTimes) {
  Rng rng(11);
  const Eigen::VectorXd t = UniformTimes(2001, 1e-3, 5.0);  // starts at 5 s: the fit must be local
  ExpectExactForPolynomials(t, RandomPolynomials(4, 5.7, 2.0, rng), SavitzkyGolayOptions{});
}

TEST(SavitzkyGolay, ExactForPolynomialsUpToOrderOnJitteredTimes) {
  Rng rng(12);
  const Eigen::VectorXd t = JitteredTimes(1500, 4.5e-3, 0.5, 0.0, rng);
  ExpectExactForPolynomials(t, RandomPolynomials(4, 3.1, 6.0, rng), SavitzkyGolayOptions{4, 0.1});
  ExpectExactForPolynomials(t, RandomPolynomials(2, 1.0, 6.0, rng), SavitzkyGolayOptions{2, 0.05});
  ExpectExactForPolynomials(t, RandomPolynomials(6, 2.0, 6.0, rng), SavitzkyGolayOptions{6, 0.2});
}

TEST(SavitzkyGolay, WindowNarrowerThanSamplingWidensToNearestSamples) {
  // 10 ms steps and a 1 ms window: no window holds 5 samples, so each fit uses the 5 nearest.
  Rng rng(13);
  const Eigen::VectorXd t = JitteredTimes(60, 0.01, 0.3, 0.0, rng);
  ExpectExactForPolynomials(t, RandomPolynomials(4, 0.2, 0.6, rng), SavitzkyGolayOptions{4, 1e-3});

  // A non-polynomial signal: sample 30 must equal a direct fit to samples 28..32 (the 5 nearest
  // for a symmetric-enough neighbourhood, chosen here by the test's own distance sort).
  Eigen::MatrixXd x(t.size(), 1);
  for (int i = 0; i < t.size(); ++i) x(i, 0) = std::sin(7.0 * t[i]) + std::exp(t[i]);
  const SavitzkyGolayResult r = SavitzkyGolay(t, x, SavitzkyGolayOptions{4, 1e-3});
  const int i = 30;
  std::vector<int> idx(t.size());
  for (int k = 0; k < t.size(); ++k) idx[k] = k;
  std::sort(idx.begin(), idx.end(), [&](int a, int b) { return std::abs(t[a] - t[i]) < std::abs(t[b] - t[i]); });
  Eigen::MatrixXd V(5, 5);
  Eigen::VectorXd y(5);
  for (int row = 0; row < 5; ++row) {
    const double s = t[idx[row]] - t[i];
    for (int k = 0; k < 5; ++k) V(row, k) = std::pow(s, k);
    y[row] = x(idx[row], 0);
  }
  const Eigen::VectorXd c = V.fullPivLu().solve(y);  // 5 points, order 4: interpolation
  EXPECT_NEAR(r.value(i, 0), c[0], 1e-9);
  EXPECT_NEAR(r.first(i, 0), c[1], 1e-7);
  EXPECT_NEAR(r.second(i, 0), 2.0 * c[2], 1e-5);
}

/// Direct least-squares fit (the test's own: column-pivoting QR of the Vandermonde matrix in
/// (t - t_i) / window) of the samples with lo <= t <= hi, evaluated at t_i.
Eigen::Vector3d DirectFit(const Eigen::VectorXd& t, const Eigen::VectorXd& x, int i, double lo, double hi, int order, double window) {
  std::vector<int> rows;
  for (int k = 0; k < t.size(); ++k) {
    if (t[k] >= lo - 1e-12 && t[k] <= hi + 1e-12) rows.push_back(k);
  }
  Eigen::MatrixXd V(rows.size(), order + 1);
  Eigen::VectorXd y(rows.size());
  for (std::size_t r = 0; r < rows.size(); ++r) {
    const double s = (t[rows[r]] - t[i]) / window;
    for (int k = 0; k <= order; ++k) V(r, k) = std::pow(s, k);
    y[r] = x[rows[r]];
  }
  const Eigen::VectorXd c = V.colPivHouseholderQr().solve(y);
  return Eigen::Vector3d(c[0], c[1] / window, 2.0 * c[2] / (window * window));
}

TEST(SavitzkyGolay, EndsUseTheNearestFullWindow) {
  Rng rng(14);
  const double w = 0.1;
  const Eigen::VectorXd t = JitteredTimes(400, 2e-3, 0.4, 1.0, rng);
  Eigen::VectorXd x(t.size());
  for (int k = 0; k < t.size(); ++k) x[k] = std::sin(9.0 * t[k]) + 0.3 * std::cos(23.0 * t[k]) + rng.Normal(1e-3);
  const SavitzkyGolayResult r = SavitzkyGolay(t, x, SavitzkyGolayOptions{4, w});
  const double first = t[0], last = t[t.size() - 1];
  for (const int i : {0, 1, 10, 200, static_cast<int>(t.size()) - 11, static_cast<int>(t.size()) - 1}) {
    double lo = t[i] - w / 2, hi = t[i] + w / 2;
    if (lo < first) lo = first, hi = first + w;
    if (hi > last) lo = last - w, hi = last;
    const Eigen::Vector3d expected = DirectFit(t, x, i, lo, hi, 4, w);
    SCOPED_TRACE("sample " + std::to_string(i));
    EXPECT_NEAR(r.value(i, 0), expected[0], 1e-10);
    EXPECT_NEAR(r.first(i, 0), expected[1], 1e-8 * std::abs(expected[1]) + 1e-8);
    EXPECT_NEAR(r.second(i, 0), expected[2], 1e-7 * std::abs(expected[2]) + 1e-7);
  }
}

/// Sum of sinusoids a_k sin(w_k t + phi_k), with analytic derivatives.
struct Sinusoids {
  std::vector<double> a, w, phi;
  double Value(double t) const {
    double v = 0.0;
    for (std::size_t k = 0; k < a.size(); ++k) v += a[k] * std::sin(w[k] * t + phi[k]);
    return v;
  }
  double First(double t) const {
    double v = 0.0;
    for (std::size_t k = 0; k < a.size(); ++k) v += a[k] * w[k] * std::cos(w[k] * t + phi[k]);
    return v;
  }
  double Second(double t) const {
    double v = 0.0;
    for (std::size_t k = 0; k < a.size(); ++k) v -= a[k] * w[k] * w[k] * std::sin(w[k] * t + phi[k]);
    return v;
  }
};

const Sinusoids kSignal{{1.0, 0.5, 0.2}, {2.0 * M_PI * 0.3, 2.0 * M_PI * 0.9, 2.0 * M_PI * 2.0}, {0.1, 1.2, -0.7}};

TEST(SavitzkyGolay, SinusoidsWithoutNoiseMatchAnalyticDerivatives) {
  // Bias of an order-4 fit over a half window h = 0.05 s, from the first Taylor terms the
  // polynomial cannot follow (odd terms cancel to first order in a near-symmetric window), for a
  // component a sin(w t), times a filter moment K of order 1:
  //   value  ~ a (w h)^6 / 6!           0.2 (4 pi 0.05)^6 / 720      = 1.7e-5 K
  //   first  ~ a w^5 h^4 / 5!           0.2 (4 pi)^5 0.05^4 / 120    = 3.2e-3 K  (4.5e-4 K of max |x'| = 7.2)
  //   second ~ 2 a w^6 h^4 / 6!         0.4 (4 pi)^6 0.05^4 / 720    = 1.4e-2 K  (2.7e-4 K of max |x''| = 51)
  // the 2 Hz component dominating (the others are 2^6 and 7^6 times smaller). Measured (seed 15):
  // 2.7e-6, 1.3e-4 and 5.2e-4 relative; the bounds below allow K up to about 1, 2 and 4. At the ends
  // the window is one-sided (s up to 2h) and the order-5 term no longer cancels: first ~ a w^5 (2h)^4 / 5!
  // = 7e-3 K, second ~ a w^5 (2h)^3 / 5! = 1.0e-2 K relative; measured 7e-4 and 1.6e-2.
  Rng rng(15);
  const Eigen::VectorXd t = JitteredTimes(5000, 5e-3, 0.35, 0.0, rng);
  Eigen::MatrixXd x(t.size(), 1), d1(t.size(), 1), d2(t.size(), 1);
  for (int i = 0; i < t.size(); ++i) {
    x(i, 0) = kSignal.Value(t[i]);
    d1(i, 0) = kSignal.First(t[i]);
    d2(i, 0) = kSignal.Second(t[i]);
  }
  const SavitzkyGolayResult r = SavitzkyGolay(t, x, SavitzkyGolayOptions{});
  const auto interior = Eigen::seq(50, t.size() - 51);  // beyond the ends' one-sided windows
  EXPECT_LT((r.value(interior, 0) - x(interior, 0)).cwiseAbs().maxCoeff(), 2e-5);
  EXPECT_LT((r.first(interior, 0) - d1(interior, 0)).cwiseAbs().maxCoeff(), 1e-3 * d1.cwiseAbs().maxCoeff());
  EXPECT_LT((r.second(interior, 0) - d2(interior, 0)).cwiseAbs().maxCoeff(), 1e-3 * d2.cwiseAbs().maxCoeff());
  EXPECT_LT((r.first - d1).cwiseAbs().maxCoeff(), 3e-3 * d1.cwiseAbs().maxCoeff());
  EXPECT_LT((r.second - d2).cwiseAbs().maxCoeff(), 5e-2 * d2.cwiseAbs().maxCoeff());
}

TEST(SavitzkyGolay, NoiseInDerivativesMatchesTheFilterGain) {
  // White noise sigma on x gives, in a linear estimate sum_j g_j x_j, an error of standard deviation
  // sigma ||g||. On a uniform grid the interior gains g are the same for every sample; the test
  // computes them itself (pseudo-inverse of the Vandermonde matrix of one centred window) and
  // checks the RMS error against the analytic derivative (bias <= 1e-3 relative, see above, far
  // below the noise) within 15 %: with 20000 samples and windows of 101 the RMS is averaged over
  // about 200 independent windows, so its relative spread is about 1 / sqrt(2 * 200) = 5 %.
  const double dt = 1e-3, sigma = 1e-3, w = 0.1;
  const int N = 20000;
  const Eigen::VectorXd t = UniformTimes(N, dt, 0.0);
  Rng rng(16);
  Eigen::MatrixXd x(N, 1), d0(N, 1), d1(N, 1), d2(N, 1);
  for (int i = 0; i < N; ++i) {
    d0(i, 0) = kSignal.Value(t[i]);
    d1(i, 0) = kSignal.First(t[i]);
    d2(i, 0) = kSignal.Second(t[i]);
    x(i, 0) = d0(i, 0) + rng.Normal(sigma);
  }
  const SavitzkyGolayResult r = SavitzkyGolay(t, x, SavitzkyGolayOptions{4, w});

  const int half = 50;  // 101 samples in a centred window
  Eigen::MatrixXd V(2 * half + 1, 5);
  for (int k = -half; k <= half; ++k) {
    for (int p = 0; p < 5; ++p) V(k + half, p) = std::pow(k * dt, p);
  }
  const Eigen::MatrixXd G = V.completeOrthogonalDecomposition().pseudoInverse();  // rows: coefficients
  const double expected[3] = {sigma * G.row(0).norm(), sigma * G.row(1).norm(), 2.0 * sigma * G.row(2).norm()};

  const auto interior = Eigen::seq(half, N - 1 - half);
  auto rms = [&](const Eigen::MatrixXd& estimate, const Eigen::MatrixXd& truth) {
    return std::sqrt((estimate(interior, 0) - truth(interior, 0)).squaredNorm() / static_cast<double>(N - 2 * half));
  };
  const double measured[3] = {rms(r.value, d0), rms(r.first, d1), rms(r.second, d2)};
  for (int k = 0; k < 3; ++k) {
    SCOPED_TRACE("derivative " + std::to_string(k));
    EXPECT_GT(measured[k], 0.85 * expected[k]);
    EXPECT_LT(measured[k], 1.15 * expected[k]);
  }
  // Noise reduction: the smoothed value is better than the raw samples, and the derivative far
  // better than a central difference (noise sigma / (sqrt(2) dt) = 0.71 rad/s here).
  EXPECT_LT(measured[0], 0.5 * sigma);
  EXPECT_LT(measured[1], 0.05 * sigma / (std::sqrt(2.0) * dt));
}

TEST(SavitzkyGolay, AllColumnsShareTheFitAndMatchSingleColumnRuns) {
  Rng rng(17);
  const Eigen::VectorXd t = JitteredTimes(300, 3e-3, 0.5, 0.0, rng);
  Eigen::MatrixXd x(t.size(), 3);
  for (int i = 0; i < t.size(); ++i) {
    for (int j = 0; j < 3; ++j) x(i, j) = std::sin((j + 1) * 4.0 * t[i]) + rng.Normal(0.01);
  }
  const SavitzkyGolayResult all = SavitzkyGolay(t, x);
  for (int j = 0; j < 3; ++j) {
    const SavitzkyGolayResult one = SavitzkyGolay(t, x.col(j));
    EXPECT_LT((all.value.col(j) - one.value.col(0)).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_LT((all.first.col(j) - one.first.col(0)).cwiseAbs().maxCoeff(), 1e-10);
    EXPECT_LT((all.second.col(j) - one.second.col(0)).cwiseAbs().maxCoeff(), 1e-8);
  }
}

template <typename F>
void ExpectInvalid(F&& call, const std::string& fragment) {
  try {
    call();
    ADD_FAILURE() << "no exception; expected one mentioning '" << fragment << "'";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
  }
}

TEST(SavitzkyGolay, RejectsInvalidInputsWithClearMessages) {
  const Eigen::VectorXd t = UniformTimes(20, 0.01, 0.0);
  const Eigen::MatrixXd x = Eigen::MatrixXd::Ones(20, 2);
  ExpectInvalid([&] { SavitzkyGolay(t, Eigen::MatrixXd::Ones(19, 2)); }, "t has 20 samples but x has 19 rows");
  ExpectInvalid([&] { SavitzkyGolay(t, x, SavitzkyGolayOptions{1, 0.1}); }, "order 1 is below 2");
  ExpectInvalid([&] { SavitzkyGolay(t, x, SavitzkyGolayOptions{4, 0.0}); }, "window 0 s is not a positive");
  ExpectInvalid([&] { SavitzkyGolay(t, x, SavitzkyGolayOptions{4, -1.0}); }, "window -1 s");
  ExpectInvalid([&] { SavitzkyGolay(t, x, SavitzkyGolayOptions{4, std::nan("")}); }, "not a positive finite width");
  ExpectInvalid([&] { SavitzkyGolay(t.head(4), x.topRows(4)); }, "4 samples are too few for a polynomial of order 4");
  Eigen::VectorXd repeated = t;
  repeated[7] = repeated[6];
  ExpectInvalid([&] { SavitzkyGolay(repeated, x); }, "t is not strictly increasing: t[7] = 0.06");
  Eigen::VectorXd decreasing = t;
  decreasing[3] = -1.0;
  ExpectInvalid([&] { SavitzkyGolay(decreasing, x); }, "t[3] = -1 is not after t[2] = 0.02");
  Eigen::VectorXd infinite = t;
  infinite[5] = INFINITY;
  ExpectInvalid([&] { SavitzkyGolay(infinite, x); }, "t[5] = inf is not finite");
  Eigen::MatrixXd nan_x = x;
  nan_x(9, 1) = std::nan("");
  ExpectInvalid([&] { SavitzkyGolay(t, nan_x); }, "x(9, 1) = nan is not finite");
}

}  // namespace
}  // namespace inertial
