// The model-free glitch screen (sample_glitches.hpp): glitches placed by construction in smooth
// signals are found, in the right row and column; noise, steps, motion that starts from rest and
// noise-free signals are not flagged.
#include "inertial/signal/sample_glitches.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "test_support.hpp"

namespace inertial {
namespace {

using testing::Rng;

// N rows of C smooth columns: sums of three sinusoids (0.05 .. 2 Hz, sampled at `rate`), amplitude
// about 1, plus white noise of standard deviation `noise`.
Eigen::MatrixXd SmoothSignals(int N, int C, double rate, double noise, unsigned seed) {
  Rng rng(seed);
  Eigen::MatrixXd m(N, C);
  for (int c = 0; c < C; ++c) {
    double f[3], a[3], phase[3];
    for (int k = 0; k < 3; ++k) {
      f[k] = rng.Uniform(0.05, 2.0);
      a[k] = rng.Uniform(0.2, 0.6);
      phase[k] = rng.Uniform(0.0, 6.283);
    }
    for (int i = 0; i < N; ++i) {
      double v = 0.0;
      for (int k = 0; k < 3; ++k) v += a[k] * std::sin(6.283185307179586 * f[k] * i / rate + phase[k]);
      m(i, c) = v + (noise > 0.0 ? rng.Normal(noise) : 0.0);
    }
  }
  return m;
}

TEST(SampleGlitches, CleanSignalsHaveNone) {
  for (unsigned seed = 1; seed <= 10; ++seed) {
    EXPECT_TRUE(FindGlitches(SmoothSignals(4000, 12, 100.0, 0.01, seed)).glitches.empty()) << "seed " << seed;
    EXPECT_TRUE(FindGlitches(SmoothSignals(4000, 12, 100.0, 0.0, seed)).glitches.empty()) << "noise-free, seed " << seed;
    EXPECT_TRUE(FindGlitches(SmoothSignals(500, 6, 1000.0, 1e-4, seed)).glitches.empty()) << "1 kHz, seed " << seed;
  }
}

TEST(SampleGlitches, OneChangedValueIsFoundWhereverItIs) {
  const Eigen::MatrixXd clean = SmoothSignals(4000, 12, 100.0, 0.01, 3);
  // Interior and both edges, large and modest: a flipped digit (x + 1), a spike of 1000, a value
  // of opposite sign and a saturation code.
  const struct { int row, column; double value; } cases[] = {
      {2000, 3, 1000.0}, {0, 0, 3.0}, {1, 7, -50.0}, {3999, 11, 1e30}, {3998, 5, 7.5}, {1234, 9, 0.0}};
  for (const auto& c : cases) {
    Eigen::MatrixXd m = clean;
    if (c.value == 0.0) {
      m(c.row, c.column) = clean(c.row, c.column) + 1.0;  // a digit changed
    } else {
      m(c.row, c.column) = c.value;
    }
    const GlitchScreen s = FindGlitches(m);
    ASSERT_EQ(s.glitches.size(), 1u) << "row " << c.row;
    EXPECT_EQ(s.glitches[0].row, c.row);
    EXPECT_EQ(s.glitches[0].column, c.column);
    EXPECT_EQ(s.glitches[0].value, m(c.row, c.column));
    EXPECT_NEAR(s.glitches[0].expected, clean(c.row, c.column), 0.05);  // noise 0.01 and curvature
    EXPECT_GT(s.glitches[0].scales, s.threshold);
  }
}

TEST(SampleGlitches, TwoAdjacentGlitchesAreBothFound) {
  Eigen::MatrixXd m = SmoothSignals(1000, 4, 100.0, 0.01, 4);
  m(500, 2) = 40.0;
  m(501, 2) = 41.0;
  m(700, 0) = -9.0;
  m(700, 1) = -90.0;  // two columns of one row: the one further out is named
  const GlitchScreen s = FindGlitches(m);
  EXPECT_EQ(s.Rows(), (std::vector<int>{500, 501, 700}));
  EXPECT_EQ(s.glitches[2].column, 1);
}

TEST(SampleGlitches, StepsAndMotionFromRestAreNotGlitches) {
  const int N = 3000;
  Eigen::MatrixXd m = Eigen::MatrixXd::Zero(N, 3);
  Rng rng(5);
  for (int i = 0; i < N; ++i) {
    m(i, 0) = (i >= 1500 ? 20.0 : 0.0) + rng.Normal(0.01);              // an impact's force step
    m(i, 1) = i >= 2000 ? 0.5 * std::sin(0.02 * (i - 2000)) : 0.0;     // at rest, then moving
    m(i, 2) = i >= 1000 && i < 1010 ? 5.0 : 0.0;                        // a 10-sample pulse
  }
  EXPECT_TRUE(FindGlitches(m).glitches.empty());
}

TEST(SampleGlitches, ShortOrBadInput) {
  EXPECT_TRUE(FindGlitches(Eigen::MatrixXd::Constant(6, 2, 1.0)).glitches.empty());
  Eigen::MatrixXd bad = SmoothSignals(100, 2, 100.0, 0.0, 1);
  bad(5, 1) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(FindGlitches(bad), std::invalid_argument);
  EXPECT_THROW(FindGlitches(SmoothSignals(100, 2, 100.0, 0.0, 1), -1.0), std::invalid_argument);
  // An explicit threshold is used as given.
  EXPECT_EQ(FindGlitches(SmoothSignals(100, 2, 100.0, 0.0, 1), 8.0).threshold, 8.0);
}

TEST(SampleGlitches, BodyLogsAreScreenedAndSelected) {
  BodyLog log;
  const Eigen::MatrixXd m = SmoothSignals(200, 15, 100.0, 0.001, 6);
  for (int i = 0; i < 200; ++i) {
    TwistWrenchSample s;
    s.t = 0.01 * i;
    s.twist = m.row(i).head<6>().transpose();
    s.wrench = m.row(i).segment<6>(6).transpose();
    log.samples.push_back(s);
    log.gravity.push_back(m.row(i).tail<3>().transpose());
  }
  EXPECT_EQ(BodySignals(log), m);
  EXPECT_EQ(BodySignalNames(log).size(), 15u);
  EXPECT_EQ(BodySignalNames(log)[3], "vx");
  log.samples[120].twist[3] = 1000.0;
  const GlitchScreen s = FindGlitches(BodySignals(log));
  ASSERT_EQ(s.Rows(), std::vector<int>{120});
  const std::string text = DescribeGlitch(log, s.glitches[0]);
  EXPECT_NE(text.find("sample 120 (t = 1.2 s): vx = 1000, expected"), std::string::npos) << text;
  const BodyLog kept = SelectBodySamples(log, {0, 5, 199});
  ASSERT_EQ(kept.samples.size(), 3u);
  ASSERT_EQ(kept.gravity.size(), 3u);
  EXPECT_EQ(kept.samples[1].t, log.samples[5].t);
  EXPECT_EQ(kept.gravity[2], log.gravity[199]);
  EXPECT_THROW(SelectBodySamples(log, {200}), std::invalid_argument);
}

}  // namespace
}  // namespace inertial
