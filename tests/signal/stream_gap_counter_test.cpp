// The gap counter of inertiald's receiver against streams whose losses are known: synthetic time
// stamps at a rate the counter is not told, with samples removed at chosen places (singles,
// bursts, one long pause) and jitter on every time stamp; the reference is the list removed.
#include "inertial/signal/stream_gap_counter.hpp"

#include <gtest/gtest.h>

#include <set>
#include <vector>

#include "allocation_counter.hpp"
#include "test_support.hpp"

namespace inertial {
namespace {

// n samples every `period` seconds from t0, each time stamp moved by up to +-jitter periods
// (uniform), the indices in `removed` left out.
std::vector<double> Stream(int n, double period, double jitter, const std::set<int>& removed, unsigned seed,
                           double t0 = 1000.0) {
  testing::Rng rng(seed);
  std::vector<double> t;
  for (int i = 0; i < n; ++i) {
    const double stamp = t0 + i * period + jitter * period * rng.Uniform(-1.0, 1.0);
    if (removed.count(i) == 0) t.push_back(stamp);
  }
  return t;
}

// Runs of consecutive indices in a set: the gaps they leave.
std::uint64_t Runs(const std::set<int>& s) {
  std::uint64_t runs = 0;
  int previous = -2;
  for (int i : s) {
    if (i != previous + 1) ++runs;
    previous = i;
  }
  return runs;
}

TEST(StreamGapCounter, CountsKnownLossesUnderJitterAtAnyRate) {
  // Jitter of 0.2 periods on each stamp: an interval moves by up to 0.4 periods, under the half
  // period the 1.5 threshold stands.
  for (const double period : {0.001, 0.005, 1.0 / 333.0}) {
    testing::Rng rng(3);
    std::set<int> removed;
    while (removed.size() < 300) {  // singles and bursts of up to 20, anywhere after the first 20
      const int at = static_cast<int>(rng.Uniform(20, 19900));
      const int length = rng.Uniform(0, 1) < 0.7 ? 1 : static_cast<int>(rng.Uniform(2, 20));
      for (int k = 0; k < length; ++k) removed.insert(at + k);
    }
    StreamGapCounter counter;
    for (double t : Stream(20000, period, 0.2, removed, 11)) counter.Observe(t);
    EXPECT_EQ(counter.lost(), removed.size()) << "period " << period;
    EXPECT_EQ(counter.gaps(), Runs(removed)) << "period " << period;
    EXPECT_NEAR(counter.median_interval(), period, 0.1 * period);
  }
}

TEST(StreamGapCounter, JitterAloneIsNoLoss) {
  // Up to 0.2 periods on each stamp: intervals between 0.6 and 1.4 periods, never a gap. (Not up
  // to 1.5: the median is itself estimated from 64 jittered intervals, a standard error of about
  // 0.02 periods here, so the threshold moves by a few hundredths of a period.)
  StreamGapCounter counter;
  for (double t : Stream(50000, 0.001, 0.2, {}, 5)) counter.Observe(t);
  EXPECT_EQ(counter.lost(), 0u);
  EXPECT_EQ(counter.gaps(), 0u);
}

TEST(StreamGapCounter, APauseIsOneLongGap) {
  // 2 s without samples in a 1 kHz stream: 1999 samples missing, one gap of 2 s.
  std::set<int> removed;
  for (int i = 1000; i < 2999; ++i) removed.insert(i);
  StreamGapCounter counter;
  for (double t : Stream(5000, 0.001, 0.0, removed, 1)) counter.Observe(t);
  EXPECT_EQ(counter.lost(), 1999u);
  EXPECT_EQ(counter.gaps(), 1u);
  EXPECT_NEAR(counter.longest_gap(), 2.0, 1e-9);
}

TEST(StreamGapCounter, OutOfOrderAndRepeatedStampsAreNotIntervals) {
  StreamGapCounter counter;
  const std::vector<double> t = Stream(1000, 0.001, 0.0, {}, 1);
  for (size_t i = 0; i < t.size(); ++i) {
    counter.Observe(t[i]);
    if (i % 10 == 5) {
      counter.Observe(t[i]);          // repeated
      counter.Observe(t[i] - 1.0);    // a second in the past
    }
  }
  EXPECT_EQ(counter.lost(), 0u);
  EXPECT_NEAR(counter.median_interval(), 0.001, 1e-12);
}

TEST(StreamGapCounter, AnInputThatDidNotDecodeIsNotLost) {
  // Samples 100 and 200 arrived but did not decode (Skip): received and rejected, not lost;
  // samples 300 and 301 never arrived: lost.
  const std::vector<double> t = Stream(500, 0.001, 0.0, {}, 1);
  StreamGapCounter counter;
  for (int i = 0; i < 500; ++i) {
    if (i == 100 || i == 200) {
      counter.Skip();
    } else if (i != 300 && i != 301) {
      counter.Observe(t[static_cast<size_t>(i)]);
    }
  }
  EXPECT_EQ(counter.lost(), 2u);
  EXPECT_EQ(counter.gaps(), 1u);
}

TEST(StreamGapCounter, NothingIsJudgedBeforeTheMedianIsKnownAndAbsurdStampsStayFinite) {
  StreamGapCounter counter;
  counter.Observe(0.0);
  counter.Observe(0.001);
  counter.Observe(0.005);  // the third interval: too early to judge
  EXPECT_EQ(counter.lost(), 0u);
  EXPECT_EQ(counter.median_interval(), 0.0);
  counter.Observe(std::nan(""));
  for (int i = 0; i < 20; ++i) counter.Observe(0.006 + 0.001 * i);
  counter.Observe(1e300);  // a time stamp beyond any year: counted, bounded
  EXPECT_GT(counter.lost(), 0u);
  EXPECT_LE(counter.lost(), static_cast<std::uint64_t>(1e15));
}

#ifndef INERTIAL_ALLOCATIONS_NOT_COUNTED
TEST(StreamGapCounter, AllocatesNothing) {
  const std::vector<double> t = Stream(2000, 0.001, 0.2, {500, 501, 900}, 2);
  StreamGapCounter counter;
  g_allocations = 0;
  g_counting = true;
  for (double s : t) counter.Observe(s);
  g_counting = false;
  EXPECT_EQ(g_allocations.load(), 0);
  EXPECT_EQ(counter.lost(), 3u);
}
#endif

}  // namespace
}  // namespace inertial
