// What `inertial replay` says about a replay, for hand-made results: the counts and throughput
// line of an LCM log and of a candump log, each reason a replay gave nothing, the origin line.
#include "inertial/runtime/replay_summary.hpp"

#include <gtest/gtest.h>

namespace inertial {
namespace {

ReplayOptions Lcm() {
  ReplayOptions o;
  o.channel = "ARM_STATE";
  return o;
}

ReplayOptions Can() {
  ReplayOptions o;
  o.can = CanConfig{};
  return o;
}

TEST(ReplaySummary, CountsAndThroughputOfAnLcmLog) {
  ReplayResult r;
  r.events = 130;
  r.counters.received = 100;
  r.counters.accepted = 96;
  r.counters.Reject(Rejection::kDecode, 3);
  r.counters.Reject(Rejection::kOutlier, 1);
  r.samples_per_second = 48123.9;
  r.seconds = 0.0125;
  EXPECT_EQ(ReplaySummaryText("run.lcm", Lcm(), r),
            "replayed run.lcm: 130 events, 100 on ARM_STATE; accepted 96, rejected 4 (decode 3, outlier 1)\n"
            "throughput: 48123 samples/s (0.0125 s)\n");
  r.counters = SampleCounters{};
  r.counters.received = r.counters.accepted = 100;
  EXPECT_EQ(ReplaySummaryText("run.lcm", Lcm(), r),
            "replayed run.lcm: 130 events, 100 on ARM_STATE; accepted 100, rejected 0\n"
            "throughput: 48123 samples/s (0.0125 s)\n");
}

TEST(ReplaySummary, ACandumpLogCountsLinesAndTicks) {
  ReplayResult r;
  r.events = 40;
  r.counters.received = 36;
  r.counters.accepted = 11;
  r.counters.Reject(Rejection::kBadLine, 4);
  r.samples = 12;
  r.lines_not_frames = 4;
  r.samples_per_second = 2.5;
  r.seconds = 2;
  EXPECT_EQ(ReplaySummaryText("motors.log", Can(), r),
            "replayed motors.log: 40 lines, 36 frame lines; accepted 11, rejected 4 (bad_line 4)\n"
            "CAN: 12 complete ticks; 4 lines that are not frames\n"
            "throughput: 2 samples/s (2 s)\n");
}

TEST(ReplaySummary, WhyAnLcmLogGaveNothing) {
  ReplayResult r;
  r.events = 0;
  EXPECT_EQ(NothingReplayedText("empty.lcm", Lcm(), r),
            "replay: empty.lcm gave the estimator no sample: no message on channel ARM_STATE; it has no channel at "
            "all; choose one with --channel");
  r.events = 7;
  r.channels = {{"LEG_STATE", 5}, {"CAMERA", 2}};
  EXPECT_EQ(NothingReplayedText("other.lcm", Lcm(), r),
            "replay: other.lcm gave the estimator no sample: no message on channel ARM_STATE; CAMERA (2 messages) "
            "LEG_STATE (5 messages); choose one with --channel");
  r.counters.received = 5;
  r.counters.Reject(Rejection::kUnknownJoint, 5);
  EXPECT_EQ(NothingReplayedText("other.lcm", Lcm(), r),
            "replay: other.lcm gave the estimator no sample: every one of the 5 messages on ARM_STATE was refused: "
            "unknown_joint 5 (the messages name joints the --model does not have)");
}

TEST(ReplaySummary, WhyAJointCsvOrACandumpLogGaveNothing) {
  ReplayResult r;
  r.counters.received = 3;
  r.counters.Reject(Rejection::kNonFinite, 2);
  r.counters.Reject(Rejection::kPriming, 1);
  EXPECT_EQ(NothingReplayedText("log.csv", Lcm(), r),
            "replay: log.csv gave the estimator no sample: every one of its 3 samples was refused: non_finite 2, "
            "priming 1");
  r = ReplayResult{};
  r.events = 9;
  EXPECT_EQ(NothingReplayedText("motors.log", Can(), r),
            "replay: motors.log gave the estimator no sample: of its 9 lines none is a candump frame");
  r.counters.received = 8;
  r.counters.Reject(Rejection::kUnknownId, 8);
  EXPECT_EQ(NothingReplayedText("motors.log", Can(), r),
            "replay: motors.log gave the estimator no sample: its 8 frame lines made 0 complete ticks (unknown_id 8): "
            "check --can-config's ids and window");
}

TEST(ReplaySummary, TheOriginOfTheFinalModelFile) {
  EXPECT_EQ(ReplayEstimateOrigin("run.lcm", 1234, "gradient"),
            "the online estimate after replaying run.lcm (1234 samples, gradient)");
}

}  // namespace
}  // namespace inertial
