#include "inertial/runtime/sample_pipeline.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "cli_support.hpp"
#include "inertial/formats/model_file.hpp"
#include "inertial/model/rigid_body_regressor.hpp"
#include "simulated_robot.hpp"

namespace inertial {
namespace {

OnlineEstimatorOptions Options() {
  OnlineEstimatorOptions o;
  o.measurement_sigma = 0.3;
  return o;
}

// The pipeline is the stages composed: the same numbers as a preprocessor and an estimator called
// by hand, every outcome counted once, and the residual window's RMS computed independently.
TEST(SamplePipeline, IsThePreprocessorThenTheEstimator) {
  const RobotDynamics model = MakeRobotDynamics(LoadUrdf(testing::Example("leg3.urdf")), {});
  const JointSamples log = testing::SimulateLogs(model, testing::TrueParameters(model, {0.0}, 6), 0.3, 4.0, 13, 250).train;
  const int n = model.num_dofs(), P = model.num_parameters();
  OnlineJointEstimator in_pipeline(model, Eigen::VectorXd::Zero(P), Options());
  OnlineJointEstimator by_hand(model, Eigen::VectorXd::Zero(P), Options());
  const double window = 0.5, cutoff = 25.0;
  SamplePipeline pipeline(&in_pipeline, cutoff, window);
  StreamPreprocessor preprocess(n, cutoff);
  by_hand.SetMomentumCutoff(cutoff);  // as the pipeline does: its rows without qdd are filtered at the stream's cutoff

  Sample s = Sample::ForJoints(n);
  JointSample h;
  std::vector<double> t_accepted;
  std::vector<Eigen::VectorXd> r_accepted;
  int accepted = 0, priming = 0, out_of_order = 0, non_finite = 0;
  for (int i = 0; i < log.size(); ++i) {
    CopySample(log, i, &s.joint);
    s.joint.has_qdd = false;  // as from a source without accelerations
    if (i == 300) s.joint.tau[1] = std::nan("");  // a glitch: the estimator refuses it
    if (i == 400) s.joint.t = log.t[10];          // time going back: the preprocessor refuses it
    h = s.joint;
    const SamplePipeline::Outcome outcome = pipeline.Process(&s);
    const Rejection pre = preprocess.Process(&h);
    ASSERT_EQ(outcome.rejection, pre) << i;
    if (pre == Rejection::kPriming) {
      ++priming;
      by_hand.Prime(h);  // as the pipeline: the momentum rows start at the preprocessor's priming sample
    }
    if (pre == Rejection::kOutOfOrder) ++out_of_order;
    if (pre != Rejection::kNone) continue;
    const UpdateStatus status = by_hand.Update(h);
    ASSERT_EQ(outcome.status, status) << i;
    if (status == UpdateStatus::kNonFinite) ++non_finite;
    if (status == UpdateStatus::kAccepted) {
      ++accepted;
      t_accepted.push_back(h.t);
      r_accepted.push_back(by_hand.stream_residual());  // the torque's, as the diagnosis gets it
    }
  }
  EXPECT_EQ(in_pipeline.estimator().parameters(), by_hand.estimator().parameters());
  const SampleCounters& c = pipeline.counters();
  EXPECT_EQ(c.received, static_cast<std::uint64_t>(log.size()));
  EXPECT_EQ(c.accepted, static_cast<std::uint64_t>(accepted));
  EXPECT_EQ(priming, 1);
  EXPECT_EQ(out_of_order, 1);
  EXPECT_EQ(non_finite, 1);
  EXPECT_EQ(c[Rejection::kPriming], 1u);
  EXPECT_EQ(c[Rejection::kOutOfOrder], 1u);
  EXPECT_EQ(c[Rejection::kNonFinite], 1u);
  EXPECT_EQ(c.accepted + c.buffered + c.total_rejected(), c.received);  // buffered: held for a solve
  EXPECT_EQ(pipeline.last_time(), t_accepted.back());

  // The last complete window: windows start at an accepted sample and hold the accepted samples
  // of the next `window` seconds; the last one still open is not reported.
  std::vector<std::size_t> starts{0};
  for (std::size_t k = 1; k < t_accepted.size(); ++k) {
    if (t_accepted[k] >= t_accepted[starts.back()] + window) starts.push_back(k);
  }
  ASSERT_GE(starts.size(), 3u);
  const std::size_t a = starts[starts.size() - 2], b = starts.back();
  Eigen::VectorXd sum = Eigen::VectorXd::Zero(n);
  for (std::size_t k = a; k < b; ++k) sum += r_accepted[k].cwiseAbs2();
  const Eigen::VectorXd expected = (sum / static_cast<double>(b - a)).cwiseSqrt();
  EXPECT_LT((pipeline.ResidualRms() - expected).cwiseAbs().maxCoeff(), 1e-12 * expected.maxCoeff());
}

// A body's residual is the prediction error of the estimate before the sample.
// A log of motor currents (every joint's torque times its gain, 8 to 15) with the gains set ends
// where the torques themselves do: the pipeline divides before anything else.
TEST(SamplePipeline, ALogWithGainsIsReadInNewtonMetres) {
  const RobotDynamics model = MakeRobotDynamics(LoadUrdf(testing::Example("leg3.urdf")), {});
  const JointSamples log = testing::SimulateLogs(model, testing::TrueParameters(model, {0.0}, 6), 0.3, 4.0, 13, 250).train;
  const int n = model.num_dofs(), P = model.num_parameters();
  const Eigen::Vector3d gains(8.0, 11.5, 15.0);
  OnlineJointEstimator torques(model, Eigen::VectorXd::Zero(P), Options());
  OnlineJointEstimator currents(model, Eigen::VectorXd::Zero(P), Options());
  SamplePipeline a(&torques, 25.0, 0.5), b(&currents, 25.0, 0.5);
  b.SetLogGains(gains);
  EXPECT_THROW(b.SetLogGains(Eigen::Vector2d(1.0, 2.0)), std::invalid_argument);
  EXPECT_THROW(b.SetLogGains(Eigen::Vector3d(1.0, 0.0, 2.0)), std::invalid_argument);
  Sample s = Sample::ForJoints(n), c = Sample::ForJoints(n);
  for (int i = 0; i < log.size(); ++i) {
    CopySample(log, i, &s.joint);
    CopySample(log, i, &c.joint);
    c.joint.tau = c.joint.tau.cwiseProduct(gains);
    a.Process(&s);
    b.Process(&c);
  }
  const Eigen::VectorXd& xa = torques.estimator().parameters();
  EXPECT_LT((currents.estimator().parameters() - xa).norm(), 1e-9 * (1.0 + xa.norm()));
  EXPECT_EQ(currents.estimator().counters().accepted(), torques.estimator().counters().accepted());
}

TEST(SamplePipeline, ABodysResidualIsThePredictionBeforeTheUpdate) {
  const InertialParams prior = InertialParams::FromMassComInertia(1.0, Vector3::Zero(), 0.02 * Matrix3::Identity());
  OnlineEstimatorOptions o;
  o.measurement_sigma = 0.05;
  OnlineBodyEstimator body(prior, o);
  SamplePipeline pipeline(&body, 1.0);
  Sample s;
  s.body.t = 0.1;
  s.body.twist << 0.3, -0.2, 0.5, 0.1, 0.0, -0.1;
  s.body.acceleration << 1.0, 0.5, -0.3, 0.2, 0.1, 0.4;
  s.body.has_acceleration = true;
  s.body.gravity = Vector3(0, 0, -9.81);
  s.body.wrench << 0.1, 0.2, 0.3, 1.0, 2.0, 3.0;
  const Vector6 expected =
      s.body.wrench - RigidBodyRegressor(s.body.twist, s.body.acceleration, s.body.gravity) * prior.vector();
  const SamplePipeline::Outcome outcome = pipeline.Process(&s);
  EXPECT_TRUE(outcome.accepted());
  EXPECT_LT((pipeline.last_residual() - expected).cwiseAbs().maxCoeff(), 1e-14 * expected.cwiseAbs().maxCoeff());
  EXPECT_LT((pipeline.ResidualRms() - expected.cwiseAbs()).cwiseAbs().maxCoeff(), 1e-14 * expected.cwiseAbs().maxCoeff());
  EXPECT_EQ(pipeline.num_channels(), 6);
  EXPECT_THROW(SamplePipeline(&body, 0.0), std::invalid_argument);
}

TEST(SamplePipeline, TotalCountersAddEveryStage) {
  SampleCounters decoded, processed;
  decoded.received = 10;
  decoded.accepted = 8;
  decoded.Reject(Rejection::kDecode, 2);
  processed.received = 7;  // one of the 8 was dropped by the queue
  processed.accepted = 5;
  processed.Reject(Rejection::kPriming);
  processed.Reject(Rejection::kOutlier);
  const SampleCounters t = TotalCounters(decoded, processed, 1);
  EXPECT_EQ(t.received, 10u);
  EXPECT_EQ(t.accepted, 5u);
  EXPECT_EQ(t[Rejection::kDecode], 2u);
  EXPECT_EQ(t[Rejection::kQueueFull], 1u);
  EXPECT_EQ(t.total_rejected(), 5u);
  EXPECT_EQ(t.accepted + t.total_rejected(), t.received);  // every input accounted for
}

}  // namespace
}  // namespace inertial
