// StreamDiagnosis (stream_diagnosis.hpp): the threaded form (a ring drained by a worker) judges
// exactly what OnlineDiagnosis and ExcitationMonitor fed directly judge (the same samples in the same
// order, the reset in its place in the stream); Observe() and the worker's draining allocate nothing.
#include "inertial/diagnosis/stream_diagnosis.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "allocation_counter.hpp"
#include "estimation/leg_chain.hpp"
#include "simulated_robot.hpp"

namespace inertial {
namespace {

// Waits until the worker has drained the ring (whatever the machine's speed: emulated or sanitized).
void WaitDrained(const StreamDiagnosis& d) {
  while (d.pending() > 0) std::this_thread::sleep_for(std::chrono::milliseconds(1));
}

RobotDynamics Leg(const std::string& effects = "") {
  return RobotDynamics(testing::LegChain(testing::LegPriorLinks()), testing::kLegJoints, ParseEffectList(effects),
                       testing::NoLinks());
}

struct Stream {
  std::vector<JointSample> samples;
  std::vector<Eigen::VectorXd> residuals;  // the estimator's, before each update
  Eigen::VectorXd x;                       // its parameters at the end
  std::vector<OnlineBodyState> bodies;
};

// The leg with Coulomb friction on the knee, 16 s at 250 Hz, through the Gauss-Newton estimator.
Stream MakeStream() {
  const RobotDynamics truth = Leg("coulomb@knee");
  const Eigen::VectorXd x_true = testing::CadErrorParameters(truth, {0.1}, 3);
  const testing::SimulatedLogs logs = testing::SimulateLogs(truth, x_true, 0.05, 16.0, 4, 250);
  const RobotDynamics model = Leg();
  OnlineEstimatorOptions o;
  o.kind = EstimatorKind::kEkf;
  o.measurement_sigma = 0.05;
  OnlineJointEstimator estimator(model, Eigen::VectorXd::Zero(model.num_parameters()), o);
  Stream s;
  JointSample sample;
  for (int i = 0; i < logs.train.size(); ++i) {
    CopySample(logs.train, i, &sample);
    if (estimator.Update(sample) != UpdateStatus::kAccepted) continue;
    s.samples.push_back(sample);
    s.residuals.push_back(estimator.residual());
  }
  s.x = estimator.estimator().parameters();
  s.bodies = BodyStatesOf(estimator);
  return s;
}

TEST(StreamDiagnosis, ThreadedJudgesExactlyWhatTheDiagnosisFedDirectlyJudges) {
  const Stream stream = MakeStream();
  const RobotDynamics model = Leg();
  StreamDiagnosisOptions options = StreamDiagnosisOptionsFor(model, OnlineEstimatorOptions{});
  options.diagnosis.window_s = 10.0;
  options.capacity = 64;  // small: the worker must keep draining while samples arrive
  StreamDiagnosis threaded(model, options);
  // The reference: the two core objects fed directly, the reset at the same place.
  OnlineDiagnosis direct(model, options.diagnosis);
  ExcitationMonitor monitor(model, options.measurement_sigma, options.prior_covariance, options.excitation);
  TreeWorkspace workspace = model.MakeWorkspace();
  Eigen::MatrixXd A(model.num_dofs(), model.num_features());
  const size_t reset_at = stream.samples.size() / 4;
  for (size_t i = 0; i < stream.samples.size(); ++i) {
    if (i == reset_at) {
      threaded.Reset();
      direct.Reset();
    }
    const JointSample& s = stream.samples[i];
    threaded.Observe(s, stream.residuals[i]);
    if (threaded.pending() >= 32) WaitDrained(threaded);
    direct.Add(s.t, s.q, s.qd, s.qdd, s.tau, stream.residuals[i]);
    if (i % static_cast<size_t>(options.excitation_decimation) == 0) {
      model.Features(s.q, s.qd, s.qdd, &workspace, A);
      monitor.Add(s.t, A, options.excitation_decimation);
    }
  }
  ASSERT_EQ(threaded.dropped(), 0u);
  const StreamJudgement judged = threaded.EvaluateNow(stream.bodies, stream.x);
  const OnlineDiagnosisResult reference = direct.Evaluate(stream.bodies);
  ASSERT_EQ(judged.diagnosis.samples, reference.samples);
  EXPECT_LT(judged.diagnosis.samples, static_cast<int>(stream.samples.size() - reset_at));  // the window, after the reset
  ASSERT_EQ(judged.diagnosis.candidates.size(), reference.candidates.size());
  for (size_t c = 0; c < reference.candidates.size(); ++c) {
    EXPECT_EQ(judged.diagnosis.candidates[c].name, reference.candidates[c].name);
    EXPECT_EQ(judged.diagnosis.candidates[c].evidence.explained, reference.candidates[c].evidence.explained);
    EXPECT_EQ(judged.diagnosis.candidates[c].values, reference.candidates[c].values);
  }
  EXPECT_EQ(judged.diagnosis.num_suggestions, reference.num_suggestions);
  ASSERT_GE(reference.num_suggestions, 1);
  EXPECT_EQ(reference.candidates[0].joint, "knee");
  ASSERT_TRUE(judged.excitation.has_value());
  const ExcitationReport expected = monitor.Evaluate(stream.x);
  ASSERT_EQ(judged.excitation->quantities.size(), expected.quantities.size());
  for (size_t q = 0; q < expected.quantities.size(); ++q) {
    EXPECT_EQ(judged.excitation->quantities[q].ratio_window, expected.quantities[q].ratio_window) << q;
  }
}

// Observe() on the estimator's thread and the worker's draining (OnlineDiagnosis::Add, the
// excitation's features and information) allocate nothing once constructed.
TEST(StreamDiagnosis, ObserveAndTheWorkerAllocateNothing) {
#ifdef INERTIAL_ALLOCATIONS_NOT_COUNTED
  GTEST_SKIP() << "this test replaces malloc to count allocations, which AddressSanitizer owns; the normal build runs it";
#endif
  const Stream stream = MakeStream();
  const RobotDynamics model = Leg();
  StreamDiagnosis threaded(model, StreamDiagnosisOptionsFor(model, OnlineEstimatorOptions{}));
  g_allocations = 0;
  g_counting = true;
  for (size_t i = 0; i < stream.samples.size(); ++i) {
    threaded.Observe(stream.samples[i], stream.residuals[i]);
    if (i == stream.samples.size() / 2) threaded.Reset();
    if (threaded.pending() >= 1024) WaitDrained(threaded);
  }
  WaitDrained(threaded);
  g_counting = false;
  EXPECT_EQ(g_allocations.load(), 0);
  EXPECT_EQ(threaded.dropped(), 0u);
  EXPECT_GT(threaded.EvaluateNow(stream.bodies, stream.x).diagnosis.samples, 0);
}

}  // namespace
}  // namespace inertial
