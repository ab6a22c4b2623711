// Hidden sensor effects in simulated single-body data (the paper's free body under the wrench
// w_k(t) = sin(t + k pi / 3), Section VI), found by the held-out ranking of body_diagnosis.hpp.
#include "inertial/diagnosis/body_diagnosis.hpp"

#include <gtest/gtest.h>

#include "inertial/inertia/consistency.hpp"
#include "inertial/model/rigid_body_simulation.hpp"
#include "test_support.hpp"

namespace inertial {
namespace {

using testing::Rng;

struct Hidden {
  Vector6 velocity_bias = Vector6::Zero();
  Vector3 force_bias = Vector3::Zero();
  Vector3 moment_bias = Vector3::Zero();
};

const InertialParams& TrueBody() {
  static const InertialParams body = InertialParams::FromMassComInertia(
      0.7, Vector3(0.1, -0.2, 0.05), (Matrix3() << 0.3, 0.02, -0.01, 0.02, 0.25, 0.03, -0.01, 0.03, 0.4).finished());
  return body;
}

// `seconds` of the free body from rest at `rate` Hz; twist noise uniform of width `twist_noise`
// (as the paper's, but an IMU-like level at these rates), wrench noise N(0, 0.01^2), plus the
// hidden biases.
BodyLog Simulate(double rate, double seconds, double twist_noise, const Hidden& hidden, unsigned seed) {
  std::vector<double> times;
  for (int i = 0; i <= static_cast<int>(seconds * rate); ++i) times.push_back(i / rate);
  auto wrench = [](double t) {
    Vector6 w;
    for (int k = 0; k < 6; ++k) w[k] = std::sin(t + k * M_PI / 3);
    return w;
  };
  const SimulationResult sim = SimulateRigidBody(TrueBody(), Vector6::Zero(), wrench, times);
  EXPECT_TRUE(sim.ok);
  Rng rng(seed);
  BodyLog log;
  for (size_t i = 0; i < times.size(); ++i) {
    TwistWrenchSample s;
    s.t = times[i];
    s.twist = sim.twists[i] + hidden.velocity_bias;
    s.wrench = wrench(times[i]);
    s.wrench.tail<3>() += hidden.force_bias;
    s.wrench.head<3>() += hidden.moment_bias;
    for (int k = 0; k < 6; ++k) {
      s.twist[k] += rng.Uniform(-twist_noise / 2, twist_noise / 2);
      s.wrench[k] += rng.Normal(0.01);
    }
    log.samples.push_back(s);
  }
  return log;
}

// The paper's starting body (m = 1 kg, I = 1 kg m^2 at the origin).
InertialParams PaperPrior() {
  Vector10 pi;
  pi << 1, 0, 0, 0, 1, 1, 1, 0, 0, 0;
  return InertialParams::FromVector(pi);
}

struct Pair {
  BodyDiagnosis with_hidden, clean;
};

// Diagnoses the log with the hidden effects and the same log without them (same noise): the
// latter's held-out error is the floor the right effect should reach.
Pair Diagnose(double rate, double seconds, double twist_noise, const Hidden& hidden) {
  Pair r;
  for (bool clean : {false, true}) {
    const BodyLog log = Simulate(rate, seconds, twist_noise, clean ? Hidden{} : hidden, 11);
    BodyLog train, validation;
    SplitHoldout(log, 0.3, &train, &validation);
    (clean ? r.clean : r.with_hidden) = DiagnoseBodyModel(PaperPrior(), {}, train, validation);
  }
  return r;
}

void ExpectConsistent(const BodyDiagnosis& d) {
  const BodyEffectModel model(PaperPrior(), d.effects);
  EXPECT_TRUE(CheckConsistency(model.Body(d.fit.x)).fully_consistent());
}

// The paper's velocity bias (0.1 on every twist component) at 100 Hz and 200 Hz: velocity_bias is
// the top suggestion, the fitted bias is within 0.04 of 0.1 per component, and with it the held-out
// error falls to within 3 % of the bias-free data's.
TEST(BodyDiagnosis, FindsThePapersVelocityBias) {
  Hidden hidden;
  hidden.velocity_bias.setConstant(0.1);
  for (const auto& [rate, noise] : {std::pair<double, double>{100.0, 0.005}, {200.0, 0.002}}) {
    const Pair r = Diagnose(rate, 40.0, noise, hidden);
    const BodyDiagnosis& d = r.with_hidden;
    ASSERT_GE(d.num_suggestions, 1) << rate;
    EXPECT_EQ(d.candidates[0].kind, BodyEffectKind::kVelocityBias) << rate;
    EXPECT_GT(d.candidates[0].explained, 0.3) << rate;
    EXPECT_LT((d.candidates[0].values.array() - 0.1).abs().maxCoeff(), 0.04) << d.candidates[0].values.transpose();
    EXPECT_GT(d.fit_validation.total_rms, 1.5 * r.clean.fit_validation.total_rms) << rate;
    EXPECT_LT(d.candidates[0].validation.total_rms, 1.03 * r.clean.fit_validation.total_rms) << rate;
    ExpectConsistent(d);
  }
}

// A force-sensor bias of about 10 % of the applied force: force_bias first, the bias recovered to
// 0.02 N, the error at the floor.
TEST(BodyDiagnosis, FindsAForceSensorBias) {
  Hidden hidden;
  hidden.force_bias = Vector3(0.1, -0.05, 0.08);
  const Pair r = Diagnose(100.0, 40.0, 0.005, hidden);
  const BodyDiagnosis& d = r.with_hidden;
  ASSERT_GE(d.num_suggestions, 1);
  EXPECT_EQ(d.candidates[0].kind, BodyEffectKind::kForceBias);
  EXPECT_LT((d.candidates[0].values - hidden.force_bias).cwiseAbs().maxCoeff(), 0.02) << d.candidates[0].values.transpose();
  EXPECT_LT(d.candidates[0].validation.total_rms, 1.03 * r.clean.fit_validation.total_rms);
  ExpectConsistent(d);
}

// A moment bias of about 10 % of the applied moment.
TEST(BodyDiagnosis, FindsAMomentBias) {
  Hidden hidden;
  hidden.moment_bias = Vector3(0.05, 0.05, -0.1);
  const Pair r = Diagnose(100.0, 40.0, 0.005, hidden);
  const BodyDiagnosis& d = r.with_hidden;
  ASSERT_GE(d.num_suggestions, 1);
  EXPECT_EQ(d.candidates[0].kind, BodyEffectKind::kMomentBias);
  EXPECT_LT((d.candidates[0].values - hidden.moment_bias).cwiseAbs().maxCoeff(), 0.02) << d.candidates[0].values.transpose();
  EXPECT_LT(d.candidates[0].validation.total_rms, 1.03 * r.clean.fit_validation.total_rms);
}

// Clean data: nothing is suggested; with the effect already in the model, nothing either.
TEST(BodyDiagnosis, SuggestsNothingOnCleanDataOrOnceTheEffectIsModelled) {
  const Pair r = Diagnose(100.0, 40.0, 0.005, Hidden{});
  EXPECT_EQ(r.with_hidden.num_suggestions, 0) << ToString(r.with_hidden.candidates[0].kind) << " "
                                              << r.with_hidden.candidates[0].explained;
  EXPECT_EQ(r.with_hidden.candidates.size(), 4u);
  Hidden hidden;
  hidden.velocity_bias.setConstant(0.1);
  const BodyLog log = Simulate(100.0, 40.0, 0.005, hidden, 11);
  BodyLog train, validation;
  SplitHoldout(log, 0.3, &train, &validation);
  const BodyDiagnosis d = DiagnoseBodyModel(PaperPrior(), {BodyEffectKind::kVelocityBias}, train, validation);
  EXPECT_EQ(d.num_suggestions, 0) << ToString(d.candidates[0].kind) << " " << d.candidates[0].explained;
  EXPECT_EQ(d.candidates.size(), 3u);
  EXPECT_LT(d.fit_validation.total_rms, 1.03 * r.clean.fit_validation.total_rms);
}

TEST(BodyDiagnosis, RejectsBadLogs) {
  BodyLog log = Simulate(10.0, 1.0, 0.0, Hidden{}, 1);
  BodyLog a, b;
  EXPECT_THROW(SplitHoldout(log, 1.0, &a, &b), std::invalid_argument);
  log.samples.resize(4);
  EXPECT_THROW(SplitHoldout(log, 0.3, &a, &b), std::invalid_argument);
  log.gravity.resize(2);
  EXPECT_THROW(FitBodyModel(BodyEffectModel(PaperPrior(), {}), log, {}), std::invalid_argument);
}

}  // namespace
}  // namespace inertial
