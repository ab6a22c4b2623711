#include "inertial/signal/stream_gap_counter.hpp"

#include <algorithm>
#include <cmath>

namespace inertial {

void StreamGapCounter::Observe(double t) {
  if (!std::isfinite(t)) return;
  if (!has_last_) {
    has_last_ = true;
    last_t_ = t;
    skipped_ = 0;
    return;
  }
  const double dt = t - last_t_;
  if (!(dt > 0.0)) return;  // out of order or repeated: not an interval
  last_t_ = t;
  const std::uint64_t skipped = skipped_;
  skipped_ = 0;
  if (count_ >= kMinIntervals && dt > kGapFactor * median_) {
    // Bounded before rounding: a time stamp years ahead still gives a finite count.
    const double periods = std::min(dt / median_, 1e15);
    const auto missing = static_cast<std::uint64_t>(std::llround(periods)) - 1;
    if (missing > skipped) {
      lost_ += missing - skipped;
      ++gaps_;
      longest_gap_ = std::max(longest_gap_, dt);
    }
  }
  // Every interval enters the window, gaps too: the median stands up to gaps in up to half of the
  // window, and a stream whose rate truly changed is followed.
  intervals_[static_cast<size_t>(next_)] = dt;
  next_ = (next_ + 1) % kWindow;
  if (count_ < kWindow) ++count_;
  const auto n = static_cast<std::ptrdiff_t>(count_);
  std::copy(intervals_.begin(), intervals_.begin() + n, scratch_.begin());
  std::nth_element(scratch_.begin(), scratch_.begin() + n / 2, scratch_.begin() + n);
  median_ = scratch_[static_cast<size_t>(n / 2)];
}

}  // namespace inertial
