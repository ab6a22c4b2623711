// The fused prediction and downdate against the dense expression D P D - f W W^T written out in
// full: sizes that exercise the main panels, the last half panel and the diagonal blocks, W as
// columns of a wider matrix, and a strictly upper triangle that must be neither read nor written.
#include "inertial/estimation/online/symmetric_rank_update.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "estimation/synthetic_regression.hpp"
#include "inertial/estimation/online/symmetric_span_product.hpp"

namespace inertial {
namespace {

using testing::RandomMatrix;
using testing::Rng;

TEST(ScaledSymmetricRankUpdate, EqualsTheDenseExpressionOnTheLowerTriangle) {
  Rng rng(21);
  for (int blocks : {1, 2, 3, 5, 10}) {
    const int n = blocks * kSpanBlock;
    for (int m : {1, 3, 6, 7}) {
      const Eigen::MatrixXd A = RandomMatrix(rng, n, n);
      const Eigen::MatrixXd sym = A * A.transpose();
      const Eigen::VectorXd d = Eigen::VectorXd::Ones(n) + 0.1 * RandomMatrix(rng, n, 1).cwiseAbs();
      Eigen::MatrixXd wide = RandomMatrix(rng, n, m + 2);
      const double f = 0.7;
      const Eigen::MatrixXd W = wide.middleCols(1, m);
      const Eigen::MatrixXd expected = d.asDiagonal() * sym * d.asDiagonal() - f * W * W.transpose();
      Eigen::MatrixXd P = sym;
      P.triangularView<Eigen::StrictlyUpper>().setConstant(1e300);  // neither read nor written
      ScaledSymmetricRankUpdate(P, d, wide.middleCols(1, m), f);
      const Eigen::MatrixXd lower_error = (P - expected).triangularView<Eigen::Lower>();
      EXPECT_LT(lower_error.cwiseAbs().maxCoeff(), 1e-13 * expected.cwiseAbs().maxCoeff()) << "n " << n << " m " << m;
      const Eigen::MatrixXd upper = P.triangularView<Eigen::StrictlyUpper>();
      Eigen::MatrixXd untouched = Eigen::MatrixXd::Zero(n, n);
      untouched.triangularView<Eigen::StrictlyUpper>().setConstant(1e300);
      EXPECT_EQ(upper, untouched) << "n " << n << " m " << m;
    }
  }
}

// With d = 1 and f = 0 nothing changes, bit for bit (what an update with forgetting off relies on
// for the diagonal scaling: x * 1 == x).
TEST(ScaledSymmetricRankUpdate, UnitScalingAndZeroRankChangeNothing) {
  Rng rng(22);
  const int n = 3 * kSpanBlock;
  const Eigen::MatrixXd A = RandomMatrix(rng, n, n);
  Eigen::MatrixXd P = A * A.transpose();
  const Eigen::MatrixXd before = P;
  ScaledSymmetricRankUpdate(P, Eigen::VectorXd::Ones(n), RandomMatrix(rng, n, 2), 0.0);
  EXPECT_EQ(P, before);
}

// The span-sorted update against the dense P - f W W^T: W's columns zero above random, ascending
// starts (one column entirely zero, sorted last with start n), on a diagonal block of a larger
// matrix whose other elements must stay as they are.
TEST(SymmetricSpanRankUpdate, EqualsTheDenseExpressionWithColumnsSortedByTheirStart) {
  Rng rng(23);
  for (int blocks : {1, 3, 7, 12}) {
    const int n = blocks * kSpanBlock, big = n + 2 * kSpanBlock;
    for (int m : {1, 4, 7, 13}) {
      Eigen::MatrixXd W = RandomMatrix(rng, n, m);
      std::vector<int> first(static_cast<size_t>(m));
      for (int k = 0; k < m; ++k) first[static_cast<size_t>(k)] = static_cast<int>(rng.Uniform(0, n - 1));
      std::sort(first.begin(), first.end());
      if (m > 1) first.back() = n;  // a zero row of A: never begins
      for (int k = 0; k < m; ++k) W.col(k).head(std::min(n, first[static_cast<size_t>(k)])).setZero();
      const Eigen::MatrixXd A = RandomMatrix(rng, big, big);
      Eigen::MatrixXd P = A * A.transpose();
      P.triangularView<Eigen::StrictlyUpper>().setConstant(1e300);  // neither read nor written
      Eigen::MatrixXd expected = P;
      const double f = 0.9;
      expected.block(kSpanBlock, kSpanBlock, n, n) -= f * W * W.transpose();
      SymmetricSpanRankUpdate(P.block(kSpanBlock, kSpanBlock, n, n), W, first.data(), Eigen::VectorXd::Ones(n), f);
      const Eigen::MatrixXd lower_error = (P - expected).triangularView<Eigen::Lower>();
      const Eigen::MatrixXd lower = expected.triangularView<Eigen::Lower>();
      EXPECT_LT(lower_error.cwiseAbs().maxCoeff(), 1e-13 * lower.cwiseAbs().maxCoeff()) << "n " << n << " m " << m;
      Eigen::MatrixXd untouched = Eigen::MatrixXd::Zero(big, big);
      untouched.triangularView<Eigen::StrictlyUpper>().setConstant(1e300);
      EXPECT_EQ(Eigen::MatrixXd(P.triangularView<Eigen::StrictlyUpper>()), untouched) << "n " << n << " m " << m;
    }
  }
}

}  // namespace
}  // namespace inertial
