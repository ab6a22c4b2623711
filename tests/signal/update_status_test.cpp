// The status of an update: every status has its own name, which ones are rejections, and the
// counters' totals.
#include "inertial/signal/update_status.hpp"

#include <gtest/gtest.h>

#include <set>
#include <string>

namespace inertial {
namespace {

TEST(UpdateStatus, NamesAndRejections) {
  EXPECT_EQ(ToString(UpdateStatus::kAccepted), "accepted");
  EXPECT_EQ(ToString(UpdateStatus::kNonFinite), "non_finite");
  EXPECT_EQ(ToString(UpdateStatus::kOutOfOrder), "out_of_order");
  EXPECT_EQ(ToString(UpdateStatus::kWrongSize), "wrong_size");
  EXPECT_EQ(ToString(UpdateStatus::kOutlier), "outlier");
  EXPECT_EQ(ToString(UpdateStatus::kNumerical), "numerical");
  EXPECT_EQ(ToString(UpdateStatus::kBuffered), "buffered");
  std::set<std::string> names;
  for (int k = 0; k < kNumUpdateStatuses; ++k) names.insert(std::string(ToString(static_cast<UpdateStatus>(k))));
  EXPECT_EQ(names.size(), static_cast<std::size_t>(kNumUpdateStatuses));  // no two alike
  EXPECT_FALSE(IsRejection(UpdateStatus::kAccepted));
  EXPECT_FALSE(IsRejection(UpdateStatus::kBuffered));  // kept for later, not refused
  for (UpdateStatus s : {UpdateStatus::kNonFinite, UpdateStatus::kOutOfOrder, UpdateStatus::kWrongSize,
                         UpdateStatus::kOutlier, UpdateStatus::kNumerical}) {
    EXPECT_TRUE(IsRejection(s)) << ToString(s);
  }
}

TEST(UpdateCounters, CountEachStatusAndSumTheRejections) {
  UpdateCounters c;
  EXPECT_EQ(c.accepted(), 0u);
  EXPECT_EQ(c.rejected(), 0u);
  // k + 1 samples of status k.
  for (int k = 0; k < kNumUpdateStatuses; ++k) {
    for (int i = 0; i <= k; ++i) c.Add(static_cast<UpdateStatus>(k));
  }
  for (int k = 0; k < kNumUpdateStatuses; ++k) EXPECT_EQ(c[static_cast<UpdateStatus>(k)], static_cast<std::uint64_t>(k + 1));
  EXPECT_EQ(c.accepted(), 1u);
  // Rejections: non_finite 2 + out_of_order 3 + wrong_size 4 + outlier 5 + numerical 6 (not buffered's 7).
  EXPECT_EQ(c.rejected(), 20u);
}

}  // namespace
}  // namespace inertial
