// Median and MAD (robust_statistics.hpp) on sets whose values are known by hand.
#include "inertial/signal/robust_statistics.hpp"

#include <gtest/gtest.h>

#include <stdexcept>

namespace inertial {
namespace {

TEST(RobustStatistics, MedianAndMadOfKnownSets) {
  std::vector<double> odd{5, 1, 3};
  EXPECT_EQ(Median(odd), 3.0);
  std::vector<double> even{4, 1, 3, 2};
  EXPECT_EQ(Median(even), 2.5);
  std::vector<double> huge{1e308, -1e308};
  EXPECT_EQ(Median(huge), 0.0);  // no overflow
  std::vector<double> v{1, 2, 3, 4, 100};
  const auto [median, mad] = MedianAndMad(v);
  EXPECT_EQ(median, 3.0);
  EXPECT_EQ(mad, 1.0);  // deviations 2 1 0 1 97
  std::vector<double> none;
  EXPECT_THROW(Median(none), std::invalid_argument);
}

TEST(RobustStatistics, MedianStepByHand) {
  Eigen::VectorXd t(5);
  t << 0.0, 0.01, 0.02, 0.5, 0.51;  // steps 0.01, 0.01, 0.48, 0.01
  EXPECT_DOUBLE_EQ(MedianStep(t), 0.01);
  Eigen::VectorXd even(3);
  even << 0.0, 1.0, 4.0;  // steps 1 and 3: their mean
  EXPECT_DOUBLE_EQ(MedianStep(even), 2.0);
  EXPECT_THROW(MedianStep(Eigen::VectorXd::Zero(1)), std::invalid_argument);
}

TEST(RobustStatistics, OneWildValueMovesNeither) {
  std::vector<double> v{1, 2, 3, 4, 5, 6, 1e300};
  const auto [median, mad] = MedianAndMad(v);
  EXPECT_EQ(median, 4.0);
  EXPECT_EQ(mad, 2.0);  // deviations 3 2 1 0 1 2 1e300
}

}  // namespace
}  // namespace inertial
