#include "inertial/diagnosis/residual_analysis.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "test_support.hpp"

namespace inertial {
namespace {

using testing::Rng;

// Two joints on sinusoids; the "model" misses known effects on joint 1 only.
JointSamples Motion(int N, double dt) {
  JointSamples s;
  s.joint_names = {"a", "b"};
  s.t.resize(N);
  s.q.resize(N, 2);
  s.qd.resize(N, 2);
  s.qdd.resize(N, 2);
  s.tau.resize(N, 2);
  for (int i = 0; i < N; ++i) {
    const double t = i * dt;
    s.t[i] = t;
    for (int j = 0; j < 2; ++j) {
      const double w1 = 2 * M_PI * 0.2 * (1 + j), w2 = 2 * M_PI * 0.53;
      s.q(i, j) = 0.6 * std::sin(w1 * t) + 0.2 * std::sin(w2 * t + j);
      s.qd(i, j) = 0.6 * w1 * std::cos(w1 * t) + 0.2 * w2 * std::cos(w2 * t + j);
      s.qdd(i, j) = -0.6 * w1 * w1 * std::sin(w1 * t) - 0.2 * w2 * w2 * std::sin(w2 * t + j);
      s.tau(i, j) = 3.0 * std::sin(w1 * t + 0.3);
    }
  }
  return s;
}

// The residual of a model lacking Coulomb friction 0.4 N m, viscous 0.25 N m s/rad, an offset of
// 0.1 N m, armature 0.02 kg m^2 and a spring 1.5 N m/rad shows each as minus its torque, and the
// joint fit recovers every coefficient; the other joint shows none.
TEST(ResidualAnalysis, RecoversTheSignatureOfEachMissingEffect) {
  Rng rng(1);
  const JointSamples s = Motion(20000, 0.001);
  Eigen::MatrixXd predicted = s.tau;
  const double q_mean = s.q.col(1).mean();
  for (int i = 0; i < s.size(); ++i) {
    const double v = s.qd(i, 1);
    const double missing = 0.1 + 0.4 * (v > 0 ? 1 : -1) + 0.25 * v + 0.02 * s.qdd(i, 1) + 1.5 * (s.q(i, 1) - q_mean);
    predicted(i, 1) -= missing;
    predicted(i, 0) += 0.01 * rng.Normal();
    predicted(i, 1) += 0.01 * rng.Normal();
  }
  const ResidualAnalysis a = AnalyzeResiduals(s, predicted, 1.0, 3);
  const JointResidualSignature& b = a.joints[1];
  EXPECT_NEAR(b.coefficients[kResidualMean], -0.1, 2e-3);
  EXPECT_NEAR(b.coefficients[kVelocitySign], -0.4, 2e-3);
  EXPECT_NEAR(b.coefficients[kVelocity], -0.25, 2e-3);
  EXPECT_NEAR(b.coefficients[kAcceleration], -0.02, 5e-4);
  EXPECT_NEAR(b.coefficients[kPosition], -1.5, 5e-3);
  EXPECT_GT(b.explained, 0.99);
  EXPECT_LT(b.correlations[kVelocitySign], -0.3);
  EXPECT_NEAR(b.alone[kResidualMean], (predicted.col(1) - s.tau.col(1)).mean(), 1e-12);
  const JointResidualSignature& quiet = a.joints[0];
  EXPECT_NEAR(quiet.rms, 0.01, 5e-4);
  EXPECT_LT(quiet.explained, 0.01);
  for (int k = 0; k < kResidualSignals; ++k) EXPECT_LT(std::abs(quiet.coefficients[k]), 0.01) << k;
}

// The worst windows are found in order and do not overlap; a burst in joint 0 during [12, 13) s
// comes first and names joint 0.
TEST(ResidualAnalysis, FindsTheWorstWindows) {
  Rng rng(2);
  const JointSamples s = Motion(20000, 0.001);
  Eigen::MatrixXd predicted = s.tau;
  for (int i = 0; i < s.size(); ++i) {
    for (int j = 0; j < 2; ++j) predicted(i, j) += 0.01 * rng.Normal();
    if (s.t[i] >= 12.0 && s.t[i] < 13.0) predicted(i, 0) += 0.5;
    if (s.t[i] >= 4.0 && s.t[i] < 5.0) predicted(i, 1) += 0.2;
  }
  const ResidualAnalysis a = AnalyzeResiduals(s, predicted, 1.0, 3);
  ASSERT_EQ(a.worst_windows.size(), 3u);
  EXPECT_NEAR(a.worst_windows[0].t_start, 12.0, 1e-9);
  EXPECT_EQ(a.worst_windows[0].worst_joint, 0);
  EXPECT_NEAR(a.worst_windows[0].rms, std::sqrt((0.25 + 0.0001 + 0.0001) / 2), 0.01);
  EXPECT_NEAR(a.worst_windows[1].t_start, 4.0, 1e-9);
  EXPECT_EQ(a.worst_windows[1].worst_joint, 1);
  EXPECT_GT(a.worst_windows[1].rms, a.worst_windows[2].rms);
  EXPECT_LT(a.worst_windows[2].rms, 0.02);
}

// A joint at rest (constant q, zero velocity) does not make the fit singular.
TEST(ResidualAnalysis, JointAtRestAndBadShapes) {
  JointSamples s = Motion(500, 0.01);
  s.q.col(0).setConstant(0.3);
  s.qd.col(0).setZero();
  s.qdd.col(0).setZero();
  Eigen::MatrixXd predicted = s.tau;
  predicted.col(0).array() += 0.2;
  const ResidualAnalysis a = AnalyzeResiduals(s, predicted, 0.5, 2);
  EXPECT_NEAR(a.joints[0].coefficients[kResidualMean], 0.2, 1e-9);
  EXPECT_EQ(a.joints[0].coefficients[kVelocity], 0.0);
  EXPECT_THROW(AnalyzeResiduals(s, predicted.leftCols(1), 1.0, 3), std::invalid_argument);
  EXPECT_THROW(AnalyzeResiduals(s, predicted, 0.0, 3), std::invalid_argument);
}

}  // namespace
}  // namespace inertial
