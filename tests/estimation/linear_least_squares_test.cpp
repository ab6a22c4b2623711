// The classical linear least-squares estimate: exact on noise-free data, the normal equations'
// solution on noisy data (an independent solve), the minimum residual and the rank of a
// rank-deficient regressor, and sizes checked.
#include "inertial/estimation/linear_least_squares.hpp"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
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

// Two equal columns: the combination of them is not identifiable, and the rank says so. (Only
// the rank: the pi returned for such an A is not promised; Eigen's solve divides by the rounding-
// sized pivot that rank() counts as zero.)
TEST(LinearLeastSquares, RankDeficientRegressorReportsRankNine) {
  Rng rng(3);
  LinearRegression reg;
  reg.A.resize(40, 10);
  for (int i = 0; i < reg.A.size(); ++i) reg.A.data()[i] = rng.Normal();
  reg.A.col(9) = reg.A.col(8);
  reg.b.resize(40);
  for (int i = 0; i < 40; ++i) reg.b[i] = rng.Normal();
  EXPECT_EQ(SolveLinearLeastSquares(reg).rank, 9);
  for (int i = 0; i < 40; ++i) reg.A(i, 9) += 1e-3 * rng.Normal();  // independent again, if barely
  EXPECT_EQ(SolveLinearLeastSquares(reg).rank, 10);
}

}  // namespace
}  // namespace inertial
