#include "inertial/estimation/batch/smallest_eigenvalue.hpp"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>

#include "test_support.hpp"

namespace inertial {
namespace {

using testing::Rng;

double Reference(const Eigen::MatrixXd& S) {
  return Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(S, Eigen::EigenvaluesOnly).eigenvalues()[0];
}

// Against Eigen's full symmetric eigensolver (QR iterations, an independent algorithm): random
// symmetric matrices of sizes 1-120, definite and indefinite, with eigenvalues spread over 12
// decades (as a scaled Newton Hessian's are), and clustered ones.
TEST(SmallestEigenvalue, MatchesTheFullEigensolver) {
  Rng rng(81);
  for (int trial = 0; trial < 60; ++trial) {
    const int n = 1 + static_cast<int>(rng.Uniform(0, 120));
    const Eigen::MatrixXd G = Eigen::MatrixXd::NullaryExpr(n, n, [&] { return rng.Normal(); });
    const Eigen::HouseholderQR<Eigen::MatrixXd> qr(G);
    const Eigen::MatrixXd Q = qr.householderQ();
    Eigen::VectorXd lambda(n);
    for (int i = 0; i < n; ++i) {
      const double magnitude = std::pow(10.0, rng.Uniform(-6, 6));
      lambda[i] = (trial % 3 == 0 ? 1.0 : (rng.Uniform(0, 1) < 0.3 ? -1.0 : 1.0)) * magnitude;
    }
    if (trial % 5 == 4) lambda.head(n / 2).setConstant(-2.5);  // a cluster at the bottom
    const Eigen::MatrixXd S = Q * lambda.asDiagonal() * Q.transpose();
    const Eigen::MatrixXd symmetric = 0.5 * (S + S.transpose());
    const double expected = Reference(symmetric);
    const double bound = 1e-13 * lambda.cwiseAbs().maxCoeff() * n;  // rounding of the reduction
    EXPECT_NEAR(SmallestEigenvalue(symmetric), expected, bound) << "n " << n << " trial " << trial;
    EXPECT_NEAR(SmallestEigenvalue(symmetric), lambda.minCoeff(), 1e-9 * lambda.cwiseAbs().maxCoeff());
    // With a tolerance: a lower bound within it (the rounding bound aside).
    const double x = SmallestEigenvalue(symmetric, 1e-3);
    EXPECT_LE(x, expected + bound);
    EXPECT_GE(x, expected - 1e-3 * std::abs(expected) - bound);
  }
}

TEST(SmallestEigenvalue, SmallCasesAndBadInput) {
  EXPECT_EQ(SmallestEigenvalue(Eigen::MatrixXd::Constant(1, 1, -3.0)), -3.0);
  Eigen::Matrix2d A;
  A << 2, 1, 1, 2;  // eigenvalues 1 and 3
  EXPECT_NEAR(SmallestEigenvalue(A), 1.0, 1e-15);
  EXPECT_NEAR(SmallestEigenvalue(Eigen::MatrixXd::Zero(4, 4)), 0.0, 1e-300);
  EXPECT_NEAR(SmallestEigenvalue(-Eigen::MatrixXd::Identity(5, 5)), -1.0, 1e-15);
  Eigen::MatrixXd bad = Eigen::MatrixXd::Identity(3, 3);
  bad(1, 2) = bad(2, 1) = std::nan("");
  EXPECT_TRUE(std::isnan(SmallestEigenvalue(bad)));
  EXPECT_THROW(SmallestEigenvalue(Eigen::MatrixXd(2, 3)), std::invalid_argument);
  EXPECT_THROW(SmallestEigenvalue(Eigen::MatrixXd(0, 0)), std::invalid_argument);
  EXPECT_THROW(SmallestEigenvalue(A, -1.0), std::invalid_argument);
}

}  // namespace
}  // namespace inertial
