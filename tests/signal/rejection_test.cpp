#include "inertial/signal/rejection.hpp"

#include <gtest/gtest.h>

#include <set>
#include <string>

namespace inertial {
namespace {

TEST(Rejection, EveryReasonHasItsOwnNameAndIsFoundByIt) {
  std::set<std::string> names;
  for (int k = 0; k < kNumRejections; ++k) {
    const Rejection r = static_cast<Rejection>(k);
    const std::string name(ToString(r));
    EXPECT_NE(name, "unknown") << k;  // kNumRejections covers the enum and no more
    EXPECT_TRUE(names.insert(name).second) << name;
    ASSERT_TRUE(RejectionNamed(name).has_value()) << name;
    EXPECT_EQ(*RejectionNamed(name), r);
  }
  EXPECT_EQ(ToString(static_cast<Rejection>(kNumRejections)), "unknown");
  EXPECT_FALSE(RejectionNamed("bogus").has_value());
}

TEST(Rejection, EstimatorStatusesKeepTheirNames) {
  // The estimator's statuses are published under the same words as UpdateStatus's.
  for (int k = 0; k < kNumUpdateStatuses; ++k) {
    const UpdateStatus s = static_cast<UpdateStatus>(k);
    if (IsRejection(s)) {
      EXPECT_EQ(ToString(RejectionOf(s)), ToString(s));
    } else {
      EXPECT_EQ(RejectionOf(s), Rejection::kNone);
    }
  }
}

TEST(SampleCounters, CountsEveryOutcomeOnce) {
  SampleCounters c;
  c.Count(UpdateStatus::kAccepted);
  c.Count(UpdateStatus::kAccepted);
  c.Count(UpdateStatus::kBuffered);
  c.Count(UpdateStatus::kOutlier);
  c.Reject(Rejection::kLate, 3);
  c.Reject(Rejection::kNone);  // not a rejection: not in the total
  EXPECT_EQ(c.accepted, 2u);
  EXPECT_EQ(c.buffered, 1u);
  EXPECT_EQ(c[Rejection::kOutlier], 1u);
  EXPECT_EQ(c[Rejection::kLate], 3u);
  EXPECT_EQ(c.total_rejected(), 4u);
}

}  // namespace
}  // namespace inertial
