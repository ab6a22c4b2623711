// The candidates' score, worked by hand: the mean over channels of the share of mean-square error
// removed, channels without error counting 0; the parsimony of the ranking key; and the three
// held-out conditions.
#include "inertial/diagnosis/explained_error.hpp"

#include <gtest/gtest.h>

#include <stdexcept>

namespace inertial {
namespace {

TEST(ExplainedShare, WorkedByHand) {
  // Channel 0: rms 2 -> 1 removes 3/4 of its mean square; channel 1 is unchanged.
  EXPECT_DOUBLE_EQ(ExplainedShare(Eigen::Vector2d(2.0, 1.0), Eigen::Vector2d(1.0, 1.0)), 0.375);
  // Scale does not matter: each channel counts alike.
  EXPECT_DOUBLE_EQ(ExplainedShare(Eigen::Vector2d(2000.0, 0.001), Eigen::Vector2d(1000.0, 0.0)), (0.75 + 1.0) / 2);
  // A channel already without error counts 0 (still in the mean).
  EXPECT_DOUBLE_EQ(ExplainedShare(Eigen::Vector3d(0.0, 2.0, 1.0), Eigen::Vector3d(0.5, 1.0, 0.5)), (0.0 + 0.75 + 0.75) / 3);
  // Worse held-out error: negative.
  EXPECT_DOUBLE_EQ(ExplainedShare(Eigen::VectorXd::Constant(1, 1.0), Eigen::VectorXd::Constant(1, 2.0)), -3.0);
  EXPECT_THROW(ExplainedShare(Eigen::VectorXd(), Eigen::VectorXd()), std::invalid_argument);
  EXPECT_THROW(ExplainedShare(Eigen::Vector2d(1, 1), Eigen::Vector3d(1, 1, 1)), std::invalid_argument);
}

TEST(ExplainedShare, RankingKeyPrefersTheSimplerEffect) {
  EXPECT_DOUBLE_EQ(RankingKey(0.3, 1), 0.3);
  EXPECT_DOUBLE_EQ(RankingKey(0.3, 2), 0.3 - kParsimony);
  EXPECT_DOUBLE_EQ(RankingKey(0.3, 7), 0.3 - 6 * kParsimony);
  // A spring (2 parameters) that explains a hair more than an offset (1) still ranks below it.
  EXPECT_LT(RankingKey(0.104, 2), RankingKey(0.100, 1));
}

TorqueErrors Errors(const Eigen::VectorXd& relative, double total) {
  TorqueErrors e;
  e.rms = relative;
  e.relative_rms = relative;
  e.total_rms = total;
  return e;
}

TEST(ExplainedShare, SupportNeedsSizePooledFallAndOneChannelsGain) {
  const TorqueErrors without = Errors(Eigen::Vector2d(0.20, 0.10), 1.0);
  const TorqueErrors better = Errors(Eigen::Vector2d(0.10, 0.10), 0.8);
  EXPECT_TRUE(SupportedByHeldOutData(without, better, 0.375, 0.02, 0.005));
  EXPECT_FALSE(SupportedByHeldOutData(without, better, 0.01, 0.02, 0.005));  // (a) too small a share
  const TorqueErrors pooled_worse = Errors(Eigen::Vector2d(0.10, 0.10), 1.2);
  EXPECT_FALSE(SupportedByHeldOutData(without, pooled_worse, 0.375, 0.02, 0.005));  // (b)
  const TorqueErrors tiny_gain = Errors(Eigen::Vector2d(0.197, 0.099), 0.99);
  EXPECT_FALSE(SupportedByHeldOutData(without, tiny_gain, 0.375, 0.02, 0.005));  // (c): 0.003 < 0.005
  EXPECT_TRUE(SupportedByHeldOutData(without, tiny_gain, 0.375, 0.02, 0.002));
}

}  // namespace
}  // namespace inertial
