#include "inertial/diagnosis/friction_shape.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "test_support.hpp"

namespace inertial {
namespace {

using testing::Rng;

constexpr int kSamples = 4000;

// Joint velocities of an identification run: a sum of sinusoids (RMS about 0.6 rad/s), crossing
// zero some 60 times.
Eigen::VectorXd Velocities() {
  Eigen::VectorXd qd(kSamples);
  for (int i = 0; i < kSamples; ++i) {
    const double t = 0.01 * i;
    qd[i] = 0.6 * std::sin(0.9 * t) + 0.4 * std::sin(2.3 * t + 1.0) + 0.2 * std::sin(5.1 * t + 0.3);
  }
  return qd;
}

// What a model holding viscous friction and an offset leaves of `friction`: plus some viscous and
// offset part (which the shape fit must ignore) and white noise of width `noise`.
Eigen::VectorXd Residual(const Eigen::VectorXd& qd, const Eigen::VectorXd& friction, double noise, Rng& rng) {
  Eigen::VectorXd r = friction + 0.3 * qd;
  for (int i = 0; i < r.size(); ++i) r[i] += 0.05 + rng.Normal(noise);
  return r;
}

double Rms(const Eigen::VectorXd& v) { return std::sqrt(v.squaredNorm() / v.size()); }

// A Coulomb step of scale on the grid (rms 2^-5) is found at that scale; one between grid points
// within half a grid step (a factor sqrt 2); the level's noise is 5 % of the level.
TEST(FrictionShape, CoulombScaleIsFound) {
  Rng rng(71);
  const Eigen::VectorXd qd = Velocities();
  for (double v_true : {Rms(qd) / 32, 0.004, 0.05}) {
    const Eigen::VectorXd f = 0.5 * (qd / v_true).array().tanh().matrix();
    const FrictionShape s = FitFrictionShape(EffectKind::kCoulomb, "j", qd, Residual(qd, f, 0.025, rng));
    EXPECT_EQ(s.spec.kind, EffectKind::kCoulomb);
    EXPECT_EQ(s.spec.target, "j");
    EXPECT_LE(std::abs(std::log2(s.spec.velocity_scale / v_true)), 0.5 + 1e-9) << v_true << " " << s.spec.velocity_scale;
    // Nearly all of the step's energy (what viscous and offset cannot take) is the gain.
    EXPECT_GT(s.gain, 0.5 * f.squaredNorm() * 0.5);
  }
}

// Friction of 0.8 N m one way and 0.3 the other. Away from rest that is Coulomb friction of 0.55
// plus an offset of 0.25 (which the model holds); the two differ only where |qd| < v_s, where the
// asymmetric form's offset part fades. With a wide transition (v_s = 0.15 rad/s, a quarter of the
// velocity RMS) that part is large, and the asymmetric form explains more than Coulomb's single
// level; it never explains less (Coulomb is its equal-level case).
TEST(FrictionShape, AsymmetricFrictionExplainsMoreThanCoulomb) {
  Rng rng(72);
  const Eigen::VectorXd qd = Velocities();
  for (double v : {0.15, 0.01}) {
    const Eigen::ArrayXd s = (qd / v).array().tanh();
    const Eigen::VectorXd f = (0.8 * s.max(0.0) + 0.3 * s.min(0.0)).matrix();
    const Eigen::VectorXd r = Residual(qd, f, 0.02, rng);
    const FrictionShape asym = FitFrictionShape(EffectKind::kAsymmetric, "j", qd, r);
    const FrictionShape coulomb = FitFrictionShape(EffectKind::kCoulomb, "j", qd, r);
    EXPECT_GE(asym.gain, coulomb.gain);
    if (v > 0.1) {
      EXPECT_LE(std::abs(std::log2(asym.spec.velocity_scale / v)), 0.5 + 1e-9) << asym.spec.velocity_scale;
      // 0.25 (1 - |s|) has an RMS of several 0.01 N m here: over 4000 samples far above the noise
      // variance 4e-4 times the one extra level.
      EXPECT_GT(asym.gain, coulomb.gain + 100 * 0.02 * 0.02);
    }
  }
}

// The sigmoid of Gaz et al. (Panda-like: p2 = 40 s/rad, p3 = 0.025 rad/s, p1 = 0.6 N m): the fit
// finds the steepness within a factor sqrt 2 (the grid's half step) and the shift's sign and size
// within the grid's resolution, and explains more than a symmetric step can.
TEST(FrictionShape, SigmoidSteepnessAndShiftAreFound) {
  Rng rng(73);
  const Eigen::VectorXd qd = Velocities();
  const double p2 = 40.0, p3 = 0.025;
  Eigen::VectorXd f(qd.size());
  for (int i = 0; i < qd.size(); ++i) f[i] = 0.6 * SigmoidFriction(qd[i], p2, p3);
  const Eigen::VectorXd r = Residual(qd, f, 0.02, rng);
  const FrictionShape sig = FitFrictionShape(EffectKind::kSigmoid, "j", qd, r);
  const FrictionShape coulomb = FitFrictionShape(EffectKind::kCoulomb, "j", qd, r);
  EXPECT_LE(std::abs(std::log2(sig.spec.steepness / p2)), 1.0) << sig.spec.steepness;
  EXPECT_GT(sig.spec.shift, 0.0);
  EXPECT_LE(std::abs(sig.spec.steepness * sig.spec.shift - p2 * p3), 0.5) << sig.spec.shift;
  // The asymmetry p1 (S(p2 p3) - 1/2) = 0.6 * 0.23 = 0.14 N m in level: over 4000 samples of noise
  // 0.02, far above the noise's variance.
  EXPECT_GT(sig.gain, coulomb.gain + 100 * 0.02 * 0.02);
}

// Noise alone (and viscous friction and an offset, which the model holds): no shape explains more
// than the largest of the grid's chi-square(1) draws would (70 shapes: below 20 variances with
// probability > 0.99).
TEST(FrictionShape, NoiseAloneGivesNoShape) {
  Rng rng(74);
  const Eigen::VectorXd qd = Velocities();
  const double noise = 0.05;
  const Eigen::VectorXd r = Residual(qd, Eigen::VectorXd::Zero(qd.size()), noise, rng);
  for (EffectKind k : {EffectKind::kCoulomb, EffectKind::kAsymmetric, EffectKind::kSigmoid}) {
    EXPECT_LT(FitFrictionShape(k, "j", qd, r).gain, 20 * noise * noise) << ToString(k);
  }
  // A joint that never moves has no shape.
  EXPECT_EQ(FitFrictionShape(EffectKind::kCoulomb, "j", Eigen::VectorXd::Zero(10), Eigen::VectorXd::Ones(10)).gain, 0.0);
}

TEST(FrictionShape, RejectsBadInput) {
  const Eigen::VectorXd qd = Velocities();
  EXPECT_THROW(FitFrictionShape(EffectKind::kViscous, "j", qd, qd), std::invalid_argument);
  EXPECT_THROW(FitFrictionShape(EffectKind::kCoulomb, "j", qd, qd.head(10)), std::invalid_argument);
  Eigen::VectorXd bad = qd;
  bad[3] = std::nan("");
  EXPECT_THROW(FitFrictionShape(EffectKind::kSigmoid, "j", qd, bad), std::invalid_argument);
  EXPECT_EQ(FrictionShapeParameters(EffectKind::kSigmoid), 2);
  EXPECT_EQ(FrictionShapeParameters(EffectKind::kAsymmetric), 1);
  EXPECT_EQ(FrictionShapeParameters(EffectKind::kOffset), 0);
}

}  // namespace
}  // namespace inertial
