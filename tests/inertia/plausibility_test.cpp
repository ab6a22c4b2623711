#include "inertial/inertia/plausibility.hpp"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>

#include "inertial/inertia/closed_form_bodies.hpp"
#include "inertial/inertia/log_det_divergence.hpp"
#include "test_support.hpp"

namespace inertial {
namespace {

using testing::Rng;

// A consistent body of 0.1 to 5 kg within 0.3 m of the origin.
InertialParams RandomBody(Rng& rng) {
  // One draw per statement, in the order the x86-64 build drew them (see testing::Rng).
  const Pose pose{rng.Rotation(), rng.UniformVector<3>(-0.3, 0.3)};
  const Vector3 L = rng.UniformVector<3>(1e-3, 0.1);
  return BodyFromSecondMoments(rng.Uniform(0.1, 5.0), L, pose);
}

// A body scaled by s departs by the factor s along every direction: lambda = s (four times),
// d = 4 (s - 1 - log s), every ratio s, no COM shift, inertia change |s - 1|, factor max(s, 1/s).
TEST(Plausibility, ScaledBodyDepartsByItsScale) {
  const InertialParams prior = SolidBox(1.3, 0.06, 0.06, 0.34, Pose{Matrix3::Identity(), Vector3(0, 0.02, -0.12)});
  for (double s : {0.25, 0.8, 1.0, 1.5, 6.5}) {
    const InertialParams body = InertialParams::FromVector(s * prior.vector());
    const BodyPlausibility p = MeasurePlausibility(body, prior);
    EXPECT_NEAR(p.mass_ratio, s, 1e-12);
    EXPECT_NEAR(p.com_shift, 0.0, 1e-12);
    EXPECT_NEAR(p.inertia_change, std::abs(s - 1), 1e-9);
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(p.moment_ratios[i], s, 1e-9 * s);
    for (int i = 0; i < 4; ++i) EXPECT_NEAR(p.lambda[i], s, 1e-9 * s);
    EXPECT_NEAR(p.divergence, 4 * (s - 1 - std::log(s)), 1e-9);
    EXPECT_NEAR(p.factor, std::max(s, 1 / s), 1e-9 * std::max(s, 1 / s));
    EXPECT_EQ(p.Within(kDefaultPriorTolerance), std::max(s, 1 / s) <= 1.75);
    EXPECT_NEAR(p.Excess(1.0), std::max(0.0, std::abs(std::log(s)) - std::log(2.0)), 1e-9);
  }
}

// A point payload m_p at distance r from the COM of a box along its x axis: J gains the rank-one
// m_p [p;1][p;1]^T, so three eigenvalues stay 1 and one is 1 + (m_p/m0)(1 + r^2/rho^2) with
// rho^2 = a^2/12 the box's squared radius of gyration along x (Schur complement of J0). The factor
// is the largest of the mass ratio, 1 + m_p r / (m0 rho0) (the payload's first moment about the
// link's COM; rho0^2 = (a^2 + b^2 + c^2) / 12 for a box) and 1 + ||dI|| / ||I0||, the inertia
// about the new COM by the parallel-axis theorem.
TEST(Plausibility, PointPayloadAwayFromTheComMatchesTheSchurComplement) {
  const double m0 = 1.3, a = 0.34, mp = 1.5;
  const Vector3 c0(0.01, 0.02, -0.12);
  const InertialParams link = SolidBox(m0, a, 0.06, 0.05, Pose{Matrix3::Identity(), c0});
  for (double r : {0.0, 0.05, 0.2}) {
    const InertialParams payload = InertialParams::FromMassComInertia(mp, c0 + Vector3(r, 0, 0), Matrix3::Zero());
    const BodyPlausibility p = MeasurePlausibility(link + payload, link);
    const double expected = 1 + (mp / m0) * (1 + r * r / (a * a / 12));
    EXPECT_NEAR(p.lambda[3], expected, 1e-9 * expected) << "r " << r;
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(p.lambda[i], 1.0, 1e-9) << "r " << r;
    EXPECT_NEAR(p.mass_ratio, (m0 + mp) / m0, 1e-12);
    EXPECT_NEAR(p.com_shift, mp * r / (m0 + mp), 1e-12);
    const double b = 0.06, c = 0.05, m = m0 + mp;
    const double rho0 = std::sqrt((a * a + b * b + c * c) / 12);
    const Vector3 com = (m0 * c0 + mp * (c0 + Vector3(r, 0, 0))) / m;
    auto point = [](double mass, const Vector3& d) { return mass * (d.squaredNorm() * Matrix3::Identity() - d * d.transpose()); };
    const Matrix3 I0 = (m0 / 12 * Vector3(b * b + c * c, a * a + c * c, a * a + b * b)).asDiagonal();
    const Matrix3 dI = point(m0, c0 - com) + point(mp, c0 + Vector3(r, 0, 0) - com);
    const double change = Eigen::SelfAdjointEigenSolver<Matrix3>(dI).eigenvalues().cwiseAbs().maxCoeff() /
                          I0.diagonal().maxCoeff();
    EXPECT_NEAR(p.inertia_change, change, 1e-9 * (1 + change));
    EXPECT_NEAR(p.com_shift_relative, p.com_shift / rho0, 1e-9);
    EXPECT_NEAR(p.first_moment_change, mp * r / (m0 * rho0), 1e-9);
    EXPECT_NEAR(p.factor, std::max({m / m0, 1 + mp * r / (m0 * rho0), 1 + change}), 1e-9);
    EXPECT_FALSE(p.Within(kDefaultPriorTolerance)) << "a payload heavier than its link is outside the tolerance";
  }
}

// The divergence equals LogDetDivergence (eq. 14) for random pairs, the factor bounds every
// generalized Rayleigh quotient u^T J u / u^T J0 u, and the measure is invariant under a rigid
// motion applied to both bodies.
TEST(Plausibility, MatchesTheDivergenceAndBoundsEveryDirection) {
  Rng rng(14);
  for (int trial = 0; trial < 200; ++trial) {
    const InertialParams prior = RandomBody(rng);
    const InertialParams body = RandomBody(rng);
    const BodyPlausibility p = MeasurePlausibility(body, prior);
    EXPECT_NEAR(p.divergence, LogDetDivergence(body.pseudo_inertia(), prior.pseudo_inertia()),
                1e-8 * (1 + p.divergence));
    for (int k = 0; k < 50; ++k) {
      const Vector4 u = rng.UniformVector<4>(-1, 1);
      const double q = u.dot(body.pseudo_inertia() * u) / u.dot(prior.pseudo_inertia() * u);
      EXPECT_LE(q, p.lambda[3] * (1 + 1e-9));
      EXPECT_GE(q, p.lambda[0] * (1 - 1e-9));
    }
    const Matrix3 R = rng.Rotation();
    const Vector3 t = rng.UniformVector<3>(-1, 1);
    const BodyPlausibility moved = MeasurePlausibility(body.Transformed(R, t), prior.Transformed(R, t));
    EXPECT_NEAR(moved.factor, p.factor, 1e-7 * p.factor);
    EXPECT_TRUE(moved.lambda.isApprox(p.lambda, 1e-7));
    EXPECT_NEAR(moved.com_shift, p.com_shift, 1e-9);
    EXPECT_TRUE(moved.moment_ratios.isApprox(p.moment_ratios, 1e-7));
  }
}

// Margins shrink each departure toward the prior: a mass 3 kg above a 1.3 kg prior with a margin
// of 1 kg counts as 3.3 kg; a margin larger than the departure leaves none; an infinite margin
// (an undetermined quantity) leaves none; a first moment shrinks by the margin along its direction.
TEST(Plausibility, MarginsShrinkTheDeparturesTowardThePrior) {
  const InertialParams prior = SolidBox(1.3, 0.3, 0.06, 0.05);
  const InertialParams heavy = SolidBox(4.3, 0.3, 0.06, 0.05);
  DepartureMargins m;
  m.mass = 1.0;
  m.inertia_about_com.setConstant(std::numeric_limits<double>::infinity());
  EXPECT_NEAR(MeasurePlausibility(heavy, prior, m).factor, 3.3 / 1.3, 1e-12);
  EXPECT_NEAR(MeasurePlausibility(heavy, prior, m).raw_factor, std::max(4.3 / 1.3, 1 + 3.0 / 1.3), 1e-9);
  m.mass = 5.0;
  EXPECT_NEAR(MeasurePlausibility(heavy, prior, m).factor, 1.0, 1e-12);
  m.mass = std::numeric_limits<double>::infinity();
  EXPECT_NEAR(MeasurePlausibility(heavy, prior, m).factor, 1.0, 1e-12);
  // A COM shift of 0.2 m along x (first moment 0.26 kg m) with a 0.05 kg m margin along x (and 1
  // along y, which does not count).
  const InertialParams moved = SolidBox(1.3, 0.3, 0.06, 0.05, Pose{Matrix3::Identity(), Vector3(0.2, 0, 0)});
  DepartureMargins c;
  c.first_moment = Vector3(0.05 * 0.05, 1.0, 0.0).asDiagonal();
  c.inertia_about_com.setConstant(std::numeric_limits<double>::infinity());
  const double rho0 = std::sqrt((0.09 + 0.0036 + 0.0025) / 12);
  EXPECT_NEAR(MeasurePlausibility(moved, prior, c).factor, 1 + (0.26 - 0.05) / (1.3 * rho0), 1e-9);
  EXPECT_NEAR(MeasurePlausibility(moved, prior).factor, 1 + 0.2 / rho0, 1e-9);
}

TEST(Plausibility, RefusesABodyThatIsNotFullyConsistent) {
  const InertialParams prior = SolidSphere(1.0, 0.1);
  Vector10 pi = prior.vector();
  pi[0] = -1.0;
  EXPECT_THROW(MeasurePlausibility(InertialParams::FromVector(pi), prior), std::invalid_argument);
  EXPECT_THROW(MeasurePlausibility(prior, InertialParams::FromVector(pi)), std::invalid_argument);
}

}  // namespace
}  // namespace inertial
