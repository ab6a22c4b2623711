// The span product against the dense product of the symmetric matrix (both triangles written out)
// with the span's rows of G: every span position and width, garbage in P's strictly upper triangle
// (it must not be read) and in G outside the span (it must be ignored).
#include "inertial/estimation/online/symmetric_span_product.hpp"

#include <gtest/gtest.h>

#include "estimation/synthetic_regression.hpp"

namespace inertial {
namespace {

using testing::RandomMatrix;
using testing::Rng;

TEST(SymmetricSpanProduct, EqualsTheDenseSymmetricProductOverTheSpan) {
  Rng rng(11);
  for (int n : {kSpanBlock, 3 * kSpanBlock, 10 * kSpanBlock}) {
    const Eigen::MatrixXd A = RandomMatrix(rng, n, n);
    const Eigen::MatrixXd sym = A + A.transpose();
    Eigen::MatrixXd P = sym;
    P.triangularView<Eigen::StrictlyUpper>().setConstant(1e300);  // never read
    for (int c = 0; c <= n; c += kSpanBlock) {
      for (int e = c; e <= n; e += kSpanBlock) {
        const Eigen::MatrixXd G = RandomMatrix(rng, n, kSpanBlock);
        Eigen::MatrixXd G_span = Eigen::MatrixXd::Zero(n, kSpanBlock);
        G_span.middleRows(c, e - c) = G.middleRows(c, e - c);
        const Eigen::MatrixXd expected = sym * G_span;
        Eigen::MatrixXd out = Eigen::MatrixXd::Constant(n, kSpanBlock, 7.0);  // overwritten
        SymmetricSpanProduct(P, G, c, e, out);
        EXPECT_LT((out - expected).cwiseAbs().maxCoeff(), 1e-13 * (1 + expected.cwiseAbs().maxCoeff()))
            << "n " << n << " span [" << c << ", " << e << ")";
      }
    }
  }
}

// Columns of larger matrices (what the Kalman update passes: blocks of H^T and P H^T).
TEST(SymmetricSpanProduct, WorksOnColumnBlocksOfWiderMatrices) {
  Rng rng(12);
  const int n = 6 * kSpanBlock;
  const Eigen::MatrixXd A = RandomMatrix(rng, n, n);
  const Eigen::MatrixXd P = A * A.transpose();
  Eigen::MatrixXd Gwide = RandomMatrix(rng, n, 3 * kSpanBlock), out_wide = Eigen::MatrixXd::Zero(n, 3 * kSpanBlock);
  const int c = kSpanBlock, e = 5 * kSpanBlock;
  SymmetricSpanProduct(P, Gwide.middleCols(kSpanBlock, kSpanBlock), c, e, out_wide.middleCols(kSpanBlock, kSpanBlock));
  const Eigen::MatrixXd expected =
      P.middleCols(c, e - c) * Gwide.block(c, kSpanBlock, e - c, kSpanBlock);
  EXPECT_LT((out_wide.middleCols(kSpanBlock, kSpanBlock) - expected).norm(), 1e-12 * expected.norm());
  EXPECT_EQ(out_wide.leftCols(kSpanBlock).norm(), 0.0);  // the neighbours untouched
  EXPECT_EQ(out_wide.rightCols(kSpanBlock).norm(), 0.0);
}

// A diagonal block of a larger P (what the online fit's gate passes: the block over a group of rows'
// span) gives those rows of the full product when G is zero outside them.
TEST(SymmetricSpanProduct, ADiagonalBlockGivesTheSpansRowsOfTheFullProduct) {
  Rng rng(13);
  const int n = 9 * kSpanBlock, c = 2 * kSpanBlock, e = 7 * kSpanBlock;
  const Eigen::MatrixXd A = RandomMatrix(rng, n, n);
  const Eigen::MatrixXd sym = A * A.transpose();
  Eigen::MatrixXd P = sym;
  P.triangularView<Eigen::StrictlyUpper>().setConstant(1e300);  // never read
  Eigen::MatrixXd G = Eigen::MatrixXd::Zero(n, kSpanBlock);
  G.middleRows(c, e - c) = RandomMatrix(rng, e - c, kSpanBlock);
  Eigen::MatrixXd out = Eigen::MatrixXd::Constant(n, kSpanBlock, 7.0);
  SymmetricSpanProduct(P.block(c, c, e - c, e - c), G.middleRows(c, e - c), 0, e - c, out.middleRows(c, e - c));
  const Eigen::MatrixXd expected = (sym * G).middleRows(c, e - c);
  EXPECT_LT((out.middleRows(c, e - c) - expected).cwiseAbs().maxCoeff(), 1e-13 * expected.cwiseAbs().maxCoeff());
  EXPECT_EQ(out.topRows(c), Eigen::MatrixXd::Constant(c, kSpanBlock, 7.0));  // rows outside the block untouched
}

TEST(NonzeroSpan, FirstAndEndOfTheNonzeroEntries) {
  int c = -1, e = -1;
  NonzeroSpan(Eigen::VectorXd::Zero(6), &c, &e);
  EXPECT_EQ(c, 0);
  EXPECT_EQ(e, 0);
  Eigen::VectorXd v = Eigen::VectorXd::Zero(9);
  v[2] = 1e-300;
  v[6] = -3.0;
  NonzeroSpan(v, &c, &e);
  EXPECT_EQ(c, 2);
  EXPECT_EQ(e, 7);
  v.setOnes();
  NonzeroSpan(v, &c, &e);
  EXPECT_EQ(c, 0);
  EXPECT_EQ(e, 9);
}

}  // namespace
}  // namespace inertial
