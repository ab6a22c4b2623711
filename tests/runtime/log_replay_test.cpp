// Log replay: an LCM log (written as lcm-logger writes, with other channels and malformed events
// mixed in) replayed through the estimator gives exactly the estimate of feeding the same samples
// directly; so does the same log as a joint CSV, and the daemon reading the log through LCM's
// file:// provider.
#include <gtest/gtest.h>

#include "inertial/estimation/batch/joint_identification.hpp"

#include <lcm/lcm-cpp.hpp>
#include <thread>

#include "cli_support.hpp"
#include "inertial/formats/model_file.hpp"
#include "inertial/formats/joint_csv.hpp"
#include "inertial/runtime/log_replay.hpp"
#include "inertial/runtime/estimation_daemon.hpp"
#include "simulated_robot.hpp"

namespace inertial {
namespace {

namespace fs = std::filesystem;

struct Fixture {
  RobotModel robot;
  JointSamples log;
};

const Fixture& Leg() {
  static const Fixture f = [] {
    Fixture out;
    out.robot = LoadUrdf(testing::Example("leg3.urdf"));
    const RobotDynamics model = MakeRobotDynamics(out.robot, {});
    out.log = testing::SimulateLogs(model, testing::TrueParameters(model, {0.0}, 6), 0.3, 8.0, 13, 250).train;
    return out;
  }();
  return f;
}

OnlineEstimatorOptions Options() {
  OnlineEstimatorOptions o;
  o.measurement_sigma = 0.3;
  return o;
}

Eigen::VectorXd Direct(const RobotDynamics& model, const JointSamples& log) {
  OnlineJointEstimator e(model, Eigen::VectorXd::Zero(model.num_parameters()), Options());
  JointSample s;
  for (int i = 0; i < log.size(); ++i) {
    CopySample(log, i, &s);
    e.Update(s);
    if (e.SolveDue()) e.Solve();  // as replay solves, in line
  }
  e.Solve(true);
  return e.estimator().parameters();
}

void AddEvent(lcm::LogFile* f, std::int64_t n, std::int64_t t, const std::string& channel, std::vector<std::uint8_t> data) {
  lcm::LogEvent ev;
  ev.eventnum = n;
  ev.timestamp = t;
  ev.channel = channel;
  ev.datalen = static_cast<std::int32_t>(data.size());
  ev.data = data.data();
  ASSERT_EQ(f->writeEvent(&ev), 0);
}

TEST(LogReplay, SameEstimateAsFeedingTheSamplesDirectly) {
  const Fixture& f = Leg();
  const RobotDynamics model = MakeRobotDynamics(f.robot, {});
  const fs::path clean = testing::UniqueTempPath("clean.lcm"), mixed = testing::UniqueTempPath("mixed.lcm"),
                 csv = testing::UniqueTempPath("log.csv"), estimates = testing::UniqueTempPath("estimates.csv"),
                 estimate_log = testing::UniqueTempPath("estimates.lcm");
  WriteJointStateLog(clean.string(), "INERTIAL_JOINT_STATE", f.log);
  // The same samples with another channel's traffic and malformed events in between.
  {
    lcm::LogFile in(clean.string(), "r"), out(mixed.string(), "w");
    std::int64_t n = 0;
    for (const lcm::LogEvent* ev = in.readNextEvent(); ev != nullptr; ev = in.readNextEvent()) {
      const auto* d = static_cast<const std::uint8_t*>(ev->data);
      AddEvent(&out, n++, ev->timestamp, ev->channel, std::vector<std::uint8_t>(d, d + ev->datalen));
      if (n % 97 == 0) {
        AddEvent(&out, n++, ev->timestamp, "OTHER", {1, 2, 3});
        AddEvent(&out, n++, ev->timestamp, "INERTIAL_JOINT_STATE", std::vector<std::uint8_t>(d, d + ev->datalen / 2));
      }
    }
  }
  const Eigen::VectorXd direct = Direct(model, f.log);
  ReplayOptions options;
  OnlineJointEstimator from_clean(model, Eigen::VectorXd::Zero(model.num_parameters()), Options());
  const ReplayResult a = ReplayLog(clean.string(), &from_clean, options);
  EXPECT_EQ(a.counters.accepted, static_cast<std::uint64_t>(f.log.size()));
  EXPECT_EQ(from_clean.estimator().parameters(), direct);

  options.csv_path = estimates.string();
  options.log_path = estimate_log.string();
  OnlineJointEstimator from_mixed(model, Eigen::VectorXd::Zero(model.num_parameters()), Options());
  const ReplayResult b = ReplayLog(mixed.string(), &from_mixed, options);
  EXPECT_EQ(from_mixed.estimator().parameters(), direct);
  EXPECT_EQ(b.counters.accepted, static_cast<std::uint64_t>(f.log.size()));
  EXPECT_EQ(b.counters.received, static_cast<std::uint64_t>(f.log.size()) + b.counters[Rejection::kDecode]);
  EXPECT_GT(b.events, b.counters.received);  // the OTHER channel is read and skipped
  EXPECT_GT(b.samples_per_second, 1000.0);
  // The estimate trajectory: one CSV row and one estimate_t event per 0.1 s of log time.
  const std::string text = testing::ReadFile(estimates);
  const long rows = std::count(text.begin(), text.end(), '\n') - 1;
  EXPECT_NEAR(static_cast<double>(rows), 8.0 / 0.1, 2.0);
  lcm::LogFile written(estimate_log.string(), "r");
  int events = 0;
  for (const lcm::LogEvent* ev = written.readNextEvent(); ev != nullptr; ev = written.readNextEvent()) {
    EXPECT_EQ(ev->channel, "INERTIAL_ESTIMATE");
    ++events;
  }
  EXPECT_EQ(events, rows);

  // The same samples as the project's CSV (written at %.17g, read back exactly).
  WriteJointCsv(csv.string(), f.log);
  OnlineJointEstimator from_csv(model, Eigen::VectorXd::Zero(model.num_parameters()), Options());
  ReplayLog(csv.string(), &from_csv, ReplayOptions{});
  EXPECT_EQ(from_csv.estimator().parameters(), direct);

  // Not a log at all.
  const fs::path junk = testing::UniqueTempPath("junk.lcm");
  std::ofstream(junk) << "this is not an LCM log\n";
  OnlineJointEstimator e(model, Eigen::VectorXd::Zero(model.num_parameters()), Options());
  EXPECT_THROW(ReplayLog(junk.string(), &e, ReplayOptions{}), std::runtime_error);
  EXPECT_THROW(ReplayLog("/nonexistent.lcm", &e, ReplayOptions{}), std::runtime_error);
  for (const fs::path& p : {clean, mixed, csv, estimates, estimate_log, junk}) fs::remove(p);
}

// The daemon reading the log through LCM's file:// provider (as fast as it can: speed=0) ends where
// direct feeding does.
TEST(LogReplay, DaemonOnAFileProvider) {
  const Fixture& f = Leg();
  const RobotDynamics model = MakeRobotDynamics(f.robot, {});
  const fs::path log = testing::UniqueTempPath("daemon.lcm");
  WriteJointStateLog(log.string(), "INERTIAL_JOINT_STATE", f.log);
  DaemonOptions o;
  o.lcm_url = "file://" + log.string() + "?speed=0";
  o.estimator = Options();
  o.log_level = LogLevel::kError;
  o.queue_capacity = static_cast<std::size_t>(f.log.size()) + 10;  // a file arrives faster than real time
  EstimationDaemon daemon(model, o);
  std::atomic<bool> stop{false};
  std::thread runner([&] { daemon.Run(stop); });
  for (int i = 0; i < 2000 && daemon.counters().samples.accepted < static_cast<std::uint64_t>(f.log.size()); ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  stop = true;
  runner.join();
  EXPECT_EQ(daemon.counters().samples.accepted, static_cast<std::uint64_t>(f.log.size())) << daemon.CountersText();
  // The daemon solves on a thread of its own, so its statistics are summed in another order; its
  // final estimate is the same fit of the same samples up to where Levenberg-Marquardt stops in
  // the valleys only the prior holds (online_fit.hpp): the same torques.
  const Eigen::MatrixXd direct = PredictJointTorques(model, Direct(model, f.log), f.log);
  const Eigen::MatrixXd daemon_tau = PredictJointTorques(model, daemon.robot_estimator()->estimator().parameters(), f.log);
  // (identify stops at a relative cost change of 1e-7: torques agree to ~sqrt(1e-7) = 3e-4.)
  EXPECT_LT((daemon_tau - direct).norm(), 1e-3 * f.log.tau.norm());
  fs::remove(log);
}

}  // namespace
}  // namespace inertial
