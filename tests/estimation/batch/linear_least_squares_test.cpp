// The classical linear least-squares estimate: exact on noise-free data, the normal equations'
// solution on noisy data (an independent solve), the rank, the minimum-norm solution and the
// minimum residual of a rank-deficient regressor (against an SVD), and sizes checked.
#include "inertial/estimation/batch/linear_least_squares.hpp"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/SVD>
#include <stdexcept>

#include "estimation/synthetic_regression.hpp"
#include "inertial/inertia/closed_form_bodies.hpp"
#include "test_support.hpp"

namespace inertial {
namespace {

using testing::RelativeError;
using testing::Rng;
using testing::SyntheticRegression;

TEST(LinearLeastSquares, RecoversExactParametersWithoutNoise) {
  Rng rng(1);
  const InertialParams body = SolidBox(0.8, 0.2, 0.3, 0.4, Pose{rng.Rotation(), Vector3(0.1, 0.2, -0.1)});
  const LinearLeastSquaresResult r = SolveLinearLeastSquares(SyntheticRegression(rng, body, 30, 0.0));
  EXPECT_EQ(r.rank, 10);
  EXPECT_LT(RelativeError(r.pi, body.vector()), 1e-12);
  EXPECT_LT(r.cost, 1e-20);
}

TEST(LinearLeastSquares, RejectsMismatchedSizes) {
  LinearRegression reg;
  reg.A.resize(12, 10);
  reg.b.resize(6);
  EXPECT_THROW(SolveLinearLeastSquares(reg), std::invalid_argument);
}

TEST(LinearLeastSquares, NoisyDataGiveTheNormalEquationsSolution) {
  Rng rng(2);
  const InertialParams body = SolidCylinder(1.5, 0.1, 0.3);
  const LinearRegression reg = SyntheticRegression(rng, body, 50, 0.1);
  const LinearLeastSquaresResult r = SolveLinearLeastSquares(reg);
  const Eigen::MatrixXd AtA = reg.A.transpose() * reg.A;
  const Vector10 normal = AtA.ldlt().solve(reg.A.transpose() * reg.b);
  EXPECT_EQ(r.rank, 10);
  EXPECT_LT((r.pi - normal).norm() / normal.norm(), 1e-10);
  EXPECT_NEAR(r.cost, 0.5 * (reg.A * normal - reg.b).squaredNorm(), 1e-10 * r.cost);
  EXPECT_GT(r.cost, 0.0);
}

// Two equal columns: the combination of them is not identifiable, and the rank says so. The pi
// returned is the minimum-norm minimizer, checked against the pseudo-inverse from an SVD (a
// different factorization), and the cost is the true minimum: 0.5 ||(I - U U^T) b||^2 with U the
// SVD's left singular vectors of the nine nonzero singular values.
TEST(LinearLeastSquares, RankDeficientRegressorReportsRankNine) {
  Rng rng(3);
  LinearRegression reg;
  reg.A.resize(40, 10);
  for (int i = 0; i < reg.A.size(); ++i) reg.A.data()[i] = rng.Normal();
  reg.A.col(9) = reg.A.col(8);
  reg.b.resize(40);
  for (int i = 0; i < 40; ++i) reg.b[i] = rng.Normal();
  const LinearLeastSquaresResult r = SolveLinearLeastSquares(reg);
  EXPECT_EQ(r.rank, 9);

  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(reg.A, Eigen::ComputeThinU | Eigen::ComputeThinV);
  const Eigen::VectorXd& s = svd.singularValues();
  ASSERT_LT(s[9], 1e-12 * s[0]);  // the null direction (e8 - e9) / sqrt(2)
  const Eigen::MatrixXd U = svd.matrixU().leftCols(9);
  const Eigen::MatrixXd V = svd.matrixV().leftCols(9);
  const Vector10 pinv = V * (U.transpose() * reg.b).cwiseQuotient(s.head(9));
  EXPECT_LT((r.pi - pinv).norm(), 1e-12 * pinv.norm());
  EXPECT_LT(r.pi.norm(), 10.0 * reg.b.norm() / s[8]);  // bounded: no division by a rounding pivot
  // The null direction has no component in a minimum-norm solution: the two equal columns' weights
  // are equal (each half of their sum).
  EXPECT_NEAR(r.pi[8], r.pi[9], 1e-12 * pinv.norm());
  const double true_minimum = 0.5 * (reg.b - U * (U.transpose() * reg.b)).squaredNorm();
  EXPECT_NEAR(r.cost, true_minimum, 1e-12 * true_minimum);

  for (int i = 0; i < 40; ++i) reg.A(i, 9) += 1e-3 * rng.Normal();  // independent again, if barely
  EXPECT_EQ(SolveLinearLeastSquares(reg).rank, 10);
}

}  // namespace
}  // namespace inertial
