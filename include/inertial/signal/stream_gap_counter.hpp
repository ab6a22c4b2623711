/// @file stream_gap_counter.hpp
/// Samples lost before inertiald (in the network, the kernel's socket buffer, LCM's own buffer, a
/// CAN controller) never reach its counters as inputs: they show only as gaps in the stream's time
/// stamps. StreamGapCounter watches the time of every decoded sample, in arrival order, and counts
/// a gap where consecutive samples are further apart than kGapFactor times the stream's median
/// sample interval, estimated from the data (the last kWindow intervals), not from a rate given to it.
///
/// Why 1.5: with samples every T seconds, an interval with nothing lost is T and one with k samples
/// lost is (k + 1) T. 1.5 T lies halfway between no loss (T) and one lost sample (2 T), so it
/// misjudges an interval only when the time stamps' jitter moves it by more than half a period, the
/// most jitter any fixed threshold between T and 2 T can stand (less the median's own error: from
/// 64 jittered intervals, a few hundredths of T). The number lost in a gap dt is round(dt / T) - 1,
/// right under the same condition (interval jitter below T / 2).
///
/// What it cannot tell: a source that pauses (a robot that stops publishing) looks like samples
/// lost, and is counted so; the longest gap is kept, so that one pause shows as one long gap. A
/// stream whose rate drops counts its first intervals at the new rate as gaps until they are the
/// median (kWindow / 2 intervals). Before kMinIntervals intervals nothing is judged. Time stamps not
/// after the previous one (out of order, repeated) are not intervals: they are skipped. Inputs of
/// the stream that gave no sample (a message that did not decode) are likely the "missing"
/// samples, so each one noted (Skip) since the last sample is subtracted from the next gap.
///
/// Allocation-free: fixed arrays; Observe is O(kWindow) (the median by nth_element on a copy).
/// Not thread-safe.
#pragma once

#include <array>
#include <cstdint>

namespace inertial {

class StreamGapCounter {
 public:
  static constexpr int kWindow = 64;        ///< intervals the median is taken over
  static constexpr int kMinIntervals = 8;   ///< intervals seen before gaps are judged
  static constexpr double kGapFactor = 1.5;

  /// The next sample's time stamp [s] (a non-finite one is ignored).
  void Observe(double t);
  /// An input of the stream that gave no sample (e.g. a message that did not decode).
  void Skip() { ++skipped_; }

  /// Samples estimated lost in gaps.
  std::uint64_t lost() const { return lost_; }
  /// Gaps (intervals longer than kGapFactor median intervals).
  std::uint64_t gaps() const { return gaps_; }
  /// The longest gap [s] (0 if none).
  double longest_gap() const { return longest_gap_; }
  /// The median sample interval [s] (0 before kMinIntervals intervals).
  double median_interval() const { return count_ >= kMinIntervals ? median_ : 0.0; }

 private:
  std::array<double, kWindow> intervals_{}, scratch_{};
  int count_ = 0, next_ = 0;
  double last_t_ = 0.0, median_ = 0.0, longest_gap_ = 0.0;
  bool has_last_ = false;
  std::uint64_t lost_ = 0, gaps_ = 0, skipped_ = 0;
};

}  // namespace inertial
