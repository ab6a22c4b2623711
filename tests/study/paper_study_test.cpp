#include "inertial/study/paper_study.hpp"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>

#include "inertial/inertia/consistency.hpp"

namespace inertial {
namespace {

// Table I: m in [0.01, 1] kg, c in [-0.5, 0.5]^3 m, second moments L at the COM in [0.01, 1] kg m^2.
TEST(PaperStudy, SampledBodiesFollowTableI) {
  for (int i = 0; i < 2000; ++i) {
    const InertialParams body = SampleTableIBody(9, i);
    ASSERT_TRUE(IsPhysicallyConsistent(body));
    EXPECT_GE(body.mass(), 0.01);
    EXPECT_LE(body.mass(), 1.0);
    EXPECT_LE(body.com().cwiseAbs().maxCoeff(), 0.5);
    const Matrix3 I = body.rotational_inertia_about_com();
    const Matrix3 Sigma = 0.5 * I.trace() * Matrix3::Identity() - I;
    const Vector3 L = Eigen::SelfAdjointEigenSolver<Matrix3>(Sigma).eigenvalues();
    EXPECT_GE(L.minCoeff(), 0.01 - 1e-12);
    EXPECT_LE(L.maxCoeff(), 1.0 + 1e-12);
  }
  // Bodies differ and are reproducible from (seed, index).
  EXPECT_EQ(SampleTableIBody(9, 3).vector(), SampleTableIBody(9, 3).vector());
  EXPECT_NE(SampleTableIBody(9, 3).vector(), SampleTableIBody(9, 4).vector());
  EXPECT_NE(SampleTableIBody(9, 3).vector(), SampleTableIBody(10, 3).vector());
}

TEST(PaperStudy, SimulatedDataHasTheStatedNoise) {
  StudyOptions options;
  const InertialParams body = SampleTableIBody(1, 0);
  const std::vector<TwistWrenchSample> noisy = SimulateStudyBody(body, 1, 0, options);
  ASSERT_EQ(noisy.size(), 63u);  // t = 0, 0.1, ..., 6.2
  EXPECT_NEAR(noisy.back().t, 6.2, 1e-12);
  options.noise_width = 0.0;
  options.noise_bias = 0.0;
  const std::vector<TwistWrenchSample> clean = SimulateStudyBody(body, 1, 0, options);
  double sum = 0.0;
  for (std::size_t i = 0; i < noisy.size(); ++i) {
    const Vector6 e = noisy[i].twist - clean[i].twist;
    EXPECT_GE(e.minCoeff(), 0.075 - 1e-12);
    EXPECT_LE(e.maxCoeff(), 0.125 + 1e-12);
    sum += e.sum();
    EXPECT_EQ(noisy[i].wrench, StudyWrench(noisy[i].t));
  }
  EXPECT_NEAR(sum / (6.0 * noisy.size()), 0.1, 0.005);  // mean 0.1; sd of the mean 0.0018
  EXPECT_EQ(clean[0].twist, Vector6::Zero());          // starts at rest
}

TEST(PaperStudy, ResultsDoNotDependOnTheNumberOfThreads) {
  StudyOptions options;
  options.bodies = 24;
  options.seed = 5;
  options.threads = 1;
  const StudyResult one = RunStudy(options);
  options.threads = 2;
  const StudyResult two = RunStudy(options);
  for (int i = 0; i < options.bodies; ++i) {
    EXPECT_EQ(one.bodies[i].pi_linear_ls, two.bodies[i].pi_linear_ls);
    for (int k = 0; k < kStudyMethods; ++k) {
      EXPECT_EQ(one.bodies[i].methods[k].iterations, two.bodies[i].methods[k].iterations);
      EXPECT_EQ(one.bodies[i].methods[k].pi, two.bodies[i].methods[k].pi);
    }
  }
  EXPECT_EQ(one.summary.nonphysical, two.summary.nonphysical);
}

TEST(PaperStudy, RejectsBadOptions) {
  StudyOptions options;
  options.bodies = 0;
  EXPECT_THROW(RunStudy(options), std::invalid_argument);
  options.bodies = 1;
  options.sample_interval = -0.1;
  EXPECT_THROW(RunStudy(options), std::invalid_argument);
}

// The paper's findings (Section VI-B), against the full 1000-body run. Reference figures come from
// the paper, not from this code: 151/1000 linear estimates nonphysical, 42 with I not positive
// definite, every nonphysical one violating a triangle inequality, none with negative mass. Our
// random draws differ from the authors', so counts are compared within 3.5 binomial standard
// deviations.
TEST(PaperStudy, ReproducesSectionVIFindings) {
  StudyOptions options;  // 1000 bodies, the paper's settings
  options.seed = 1;
  const StudyResult r = RunStudy(options);
  const StudySummary& s = r.summary;
  auto within = [](int count, double paper_fraction, int n) {
    const double sd = std::sqrt(paper_fraction * (1 - paper_fraction) * n);
    return std::abs(count - paper_fraction * n) <= 3.5 * sd;
  };
  EXPECT_TRUE(within(s.nonphysical, 0.151, 1000)) << s.nonphysical;
  EXPECT_TRUE(within(s.not_positive_definite, 0.042, 1000)) << s.not_positive_definite;
  EXPECT_EQ(s.triangle_violations, s.nonphysical);
  EXPECT_EQ(s.negative_mass, 0);
  EXPECT_NEAR(s.mean_most_negative_eigenvalue, -0.04, 0.015);

  const MethodSummary& lc = s.methods[kLogCholesky];
  const MethodSummary& eig = s.methods[kEigenvalue];
  // Log-Cholesky: every estimate consistent, few failures, fewer iterations than the eigenvalue map.
  EXPECT_EQ(lc.inconsistent_results, 0);
  EXPECT_LE(lc.failures, 10);
  EXPECT_LT(lc.median_iterations, eig.median_iterations);
  for (const BodyOutcome& b : r.bodies) {
    EXPECT_TRUE(b.methods[kLogCholesky].consistent);
    EXPECT_LE(b.methods[kLogCholesky].iterations, 50);
  }
  // Seconds, not minutes.
  EXPECT_LT(s.wall_seconds, 60.0);
}

}  // namespace
}  // namespace inertial
