// Uncertainty of the batch identification (fit_uncertainty.hpp) and the body quantities' Jacobian
// (MassComInertiaAboutCom, parameter_layout.hpp). The Monte Carlo check on the bundled leg is in
// tests/formats/fit_uncertainty_monte_carlo_test.cpp (it reads the URDF).
#include "inertial/estimation/fit_uncertainty.hpp"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <cmath>

#include "inertial/estimation/batch/identifiability.hpp"
#include "inertial/inertia/closed_form_bodies.hpp"
#include "estimation/leg_chain.hpp"
#include "test_support.hpp"

namespace inertial {
namespace {

using testing::ExciteLeg;
using testing::Rng;

// J_mci_pi against central differences of mci(pi), at random fully consistent bodies, thin ones
// (a rod, a plate, a light body far from the origin) included. Steps are relative to each entry
// of pi so that the rounding error stays below the tolerance.
TEST(MassComInertiaAboutCom, JacobianMatchesCentralDifferences) {
  Rng rng(51);
  std::vector<InertialParams> bodies;
  for (int k = 0; k < 6; ++k) {
    Pose pose = rng.RandomPose<Pose>(0.3);
    // One draw per statement, in the order the x86-64 build drew them (see testing::Rng).
    const double z = rng.Uniform(0.02, 0.4);
    const double y = rng.Uniform(0.02, 0.4);
    const double x = rng.Uniform(0.02, 0.4);
    bodies.push_back(SolidBox(rng.Uniform(0.2, 5.0), x, y, z, pose));
  }
  bodies.push_back(SolidCylinder(0.4, 1e-4, 0.5, rng.RandomPose<Pose>(0.2)));       // a rod
  bodies.push_back(SolidBox(1.2, 0.3, 0.2, 1e-5, rng.RandomPose<Pose>(0.2)));       // a plate
  bodies.push_back(SolidSphere(1e-3, 0.01, Pose{Matrix3::Identity(), Vector3(0.5, -0.4, 0.3)}));  // light, far
  for (size_t b = 0; b < bodies.size(); ++b) {
    const Vector10 pi = bodies[b].vector();
    Matrix10 J_mci_pi;
    const Vector10 mci = MassComInertiaAboutCom(bodies[b], &J_mci_pi);
    // The value: mass, COM and the tensor's entries about the COM.
    const Matrix3 I_C = bodies[b].rotational_inertia_about_com();
    EXPECT_EQ(mci[mci_index::kMass], bodies[b].mass());
    EXPECT_LT((mci.segment<3>(mci_index::kCx) - bodies[b].com()).norm(), 1e-14);
    const Vector6 entries = (Vector6() << I_C(0, 0), I_C(1, 1), I_C(2, 2), I_C(0, 1), I_C(1, 2), I_C(0, 2)).finished();
    EXPECT_LT((mci.segment<6>(mci_index::kIxx) - entries).norm(), 1e-14 * std::max(1.0, I_C.norm()));
    for (int k = 0; k < 10; ++k) {
      const double h = 1e-6 * std::max(std::abs(pi[k]), 1e-3 * pi[pi_index::kMass]);
      Vector10 plus = pi, minus = pi;
      plus[k] += h;
      minus[k] -= h;
      const Vector10 fd = (MassComInertiaAboutCom(InertialParams::FromVector(plus)) -
                           MassComInertiaAboutCom(InertialParams::FromVector(minus))) / (2.0 * h);
      for (int i = 0; i < 10; ++i) {
        EXPECT_NEAR(J_mci_pi(i, k), fd[i], 1e-6 * std::max(std::abs(fd[i]), 1.0 / std::max(1.0, pi[pi_index::kMass])))
            << "body " << b << " d mci[" << i << "] / d pi[" << k << "]";
      }
    }
  }
}

// UncertaintyOf's new field, and the old ones unchanged: with the COM at the origin, I_C = I_O and
// the two inertia stds coincide; otherwise they follow sqrt(diag(G C G^T)) with G from J_mci_pi.
TEST(MassComInertiaAboutCom, UncertaintyOfGivesInertiaAboutComStd) {
  Rng rng(52);
  Matrix10 L = Matrix10::Zero();
  for (int i = 0; i < 10; ++i) {
    for (int j = 0; j <= i; ++j) L(i, j) = rng.Normal(i == j ? 1e-3 : 3e-4);
  }
  const Matrix10 C = L * L.transpose();
  const BodyUncertainty centred = UncertaintyOf(SolidBox(2.0, 0.3, 0.2, 0.1), C);
  EXPECT_LT((centred.inertia_about_com - centred.inertia).norm(), 1e-15);
  const InertialParams off = SolidBox(2.0, 0.3, 0.2, 0.1, Pose{rng.Rotation(), Vector3(0.1, -0.2, 0.05)});
  const BodyUncertainty u = UncertaintyOf(off, C);
  Matrix10 J;
  MassComInertiaAboutCom(off, &J);
  const Vector10 expected = (J * C * J.transpose()).diagonal().cwiseSqrt();
  EXPECT_DOUBLE_EQ(u.mass, std::sqrt(C(0, 0)));
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(u.com[k], expected[mci_index::kCx + k], 1e-12 * expected[mci_index::kCx + k]);
  for (int k = 0; k < 6; ++k) {
    EXPECT_DOUBLE_EQ(u.inertia[k], std::sqrt(C(4 + k, 4 + k)));
    EXPECT_NEAR(u.inertia_about_com[k], expected[mci_index::kIxx + k], 1e-12 * expected[mci_index::kIxx + k]);
  }
}

const std::vector<std::string>& kJoints = testing::kLegJoints;
KinematicTree Leg() { return testing::LegChain(testing::LegPriorLinks()); }

RobotDynamics LegModel(const std::string& effects) {
  return RobotDynamics(Leg(), kJoints, ParseEffectList(effects), testing::NoLinks());
}

// Closed form: with every body frozen the model is linear in the effect coefficients c (w = [pi of
// the priors; c]), the fit is linear least squares c = (A_e^T A_e)^-1 A_e^T (tau - A_b pi), and
//   s^2 = ||A w - tau||^2 / (N_rows - P_e),  cov(c) = s^2 (A_e^T A_e)^-1,
// exactly (p_eff = P_e: no prior acts on effects). Through b = e^s (Gauss-Newton, J = diag(b)),
// cov(s_i, s_j) = cov(c_i, c_j) / (c_i c_j), and std(b) = b std(s) = std(c).
TEST(FitUncertainty, EffectsOnlyMatchLinearLeastSquares) {
  Rng rng(53);
  const RobotDynamics model = LegModel("viscous,coulomb:scale=0.05,offset");
  const int Fi = model.num_inertia_features(), F = model.num_features(), Fe = F - Fi;
  Eigen::VectorXd c_true(Fe);
  for (const EffectTerm& t : model.effects()) {
    c_true[t.first_feature - Fi] = t.kind == EffectKind::kViscous ? 0.3 : t.kind == EffectKind::kCoulomb ? 0.8 : -0.4;
  }
  const JointSamples samples = ExciteLeg(model, model.ParametersFromEffectCoefficients(c_true), 600, 0.005, 0.1, rng);
  const JointNormalEquations eq = AccumulateNormalEquations(model, samples);
  const Eigen::VectorXd w_prior = model.Coefficients(Eigen::VectorXd::Zero(model.num_parameters()));
  const Eigen::MatrixXd AtA_e = eq.AtA.bottomRightCorner(Fe, Fe);
  const Eigen::VectorXd c = AtA_e.ldlt().solve(eq.Atb.tail(Fe) - eq.AtA.bottomLeftCorner(Fe, Fi) * w_prior.head(Fi));
  for (const EffectTerm& t : model.effects()) {
    if (t.kind != EffectKind::kOffset) {
      ASSERT_GT(c[t.first_feature - Fi], 0.1);  // e^s can represent it
    }
  }
  const Eigen::VectorXd x = model.ParametersFromEffectCoefficients(c);
  Eigen::VectorXd w = w_prior;
  w.tail(Fe) = c;
  const double rows = 3.0 * samples.size();
  const double s2 = SquaredError(eq, w) / (rows - Fe);
  const Eigen::MatrixXd cov_c = s2 * AtA_e.inverse();

  const std::vector<bool> frozen = {true, true, true};
  for (double gamma : {0.0, 1e-2}) {  // the prior is irrelevant with every body frozen
    const FitUncertainty u = EstimateFitUncertainty(model, eq, x, gamma, frozen);
    EXPECT_NEAR(u.effective_parameters, Fe, 1e-9 * Fe);
    EXPECT_NEAR(u.dof, rows - Fe, 1e-9 * rows);
    EXPECT_NEAR(u.noise_sigma, std::sqrt(s2), 1e-9 * std::sqrt(s2));
    EXPECT_EQ(u.undetermined_directions, 0);
    ASSERT_EQ(u.effects.size(), model.effects().size());
    for (int k = 0; k < static_cast<int>(model.effects().size()); ++k) {
      const EffectTerm& t = model.effects()[k];
      const int f = t.first_feature - Fi;
      ASSERT_EQ(u.effects[k].size(), 1u);
      EXPECT_NEAR(u.effects[k][0], std::sqrt(cov_c(f, f)), 1e-9 * std::sqrt(cov_c(f, f))) << k;
      for (const EffectTerm& o : model.effects()) {
        const int g = o.first_feature - Fi;
        const double scale = (t.kind == EffectKind::kOffset ? 1.0 : c[f]) * (o.kind == EffectKind::kOffset ? 1.0 : c[g]);
        const double expected = cov_c(f, g) / scale;
        EXPECT_NEAR(u.covariance(t.first_parameter, o.first_parameter), expected,
                    1e-9 * std::sqrt(cov_c(f, f) * cov_c(g, g)) / scale) << k;
      }
    }
    // Frozen bodies: fixed, so zero covariance, zero std, nothing held.
    EXPECT_EQ(u.covariance.topRows(30).cwiseAbs().maxCoeff(), 0.0);
    EXPECT_EQ(u.covariance.leftCols(30).cwiseAbs().maxCoeff(), 0.0);
    for (int e = 0; e < 3; ++e) {
      EXPECT_EQ(u.bodies[e].mass, 0.0);
      EXPECT_EQ(u.bodies[e].com.norm() + u.bodies[e].inertia.norm() + u.bodies[e].inertia_about_com.norm(), 0.0);
      EXPECT_FALSE(u.body_held[e].mass);
    }
  }
}

// Nothing estimated (every body frozen, no effect): no crash, zero effective parameters, every std 0.
TEST(FitUncertainty, NothingEstimatedGivesZeroStandardDeviations) {
  Rng rng(54);
  const RobotDynamics model = LegModel("");
  const JointSamples samples = ExciteLeg(model, Eigen::VectorXd::Zero(model.num_parameters()), 100, 0.005, 0.1, rng);
  const JointNormalEquations eq = AccumulateNormalEquations(model, samples);
  const FitUncertainty u =
      EstimateFitUncertainty(model, eq, Eigen::VectorXd::Zero(model.num_parameters()), 1e-2, {true, true, true});
  EXPECT_EQ(u.effective_parameters, 0.0);
  EXPECT_EQ(u.undetermined_directions, 0);
  ASSERT_EQ(u.bodies.size(), 3u);
  for (const BodyUncertainty& b : u.bodies) EXPECT_EQ(b.mass, 0.0);
}

// The first link turns about a fixed axis: its mass never enters the torques (only its first
// moment and its inertia about the axis do). Without a prior that mass is undetermined (std
// infinite, not "held": nothing holds it); with the paper's prior it is finite and held by the
// prior, and the effective number of parameters drops below P.
TEST(FitUncertainty, MassOfTheFirstLinkIsHeldByThePriorOrUndetermined) {
  Rng rng(54);
  const RobotDynamics model = LegModel("viscous");
  Eigen::VectorXd x_true = Eigen::VectorXd::Zero(model.num_parameters());
  for (int i = 0; i < 30; ++i) x_true[i] = rng.Uniform(-0.2, 0.2);
  // A leg a robot could have: each link well inside its region (body_region.hpp), so that the fit's
  // region barrier is not in play and the data and the prior alone decide what is determined.
  for (int e = 0; e < 3; ++e) {
    x_true.segment<10>(10 * e) = ShrinkIntoRegion(model.bodies()[e].map, *model.bodies()[e].region, x_true.segment<10>(10 * e));
  }
  for (const EffectTerm& t : model.effects()) x_true[t.first_parameter] = std::log(0.3);
  const JointNormalEquations eq = AccumulateNormalEquations(model, ExciteLeg(model, x_true, 1500, 0.005, 0.2, rng));
  JointIdentificationOptions options;
  options.initial = x_true;
  const Eigen::VectorXd x = IdentifyJointModel(model, eq, options).x;

  const FitUncertainty none = EstimateFitUncertainty(model, eq, x, 0.0);
  EXPECT_GT(none.undetermined_directions, 0);
  EXPECT_TRUE(std::isinf(none.bodies[0].mass));
  EXPECT_FALSE(none.body_held[0].mass);
  EXPECT_NEAR(none.effective_parameters, model.num_parameters() - none.undetermined_directions, 1e-6);
  for (int k = 0; k < 3; ++k) EXPECT_TRUE(std::isfinite(none.effects[k][0])) << k;  // friction is identifiable

  const FitUncertainty with_prior = EstimateFitUncertainty(model, eq, x, options.prior_weight);
  EXPECT_EQ(with_prior.undetermined_directions, 0);
  EXPECT_TRUE(std::isfinite(with_prior.bodies[0].mass));
  EXPECT_TRUE(with_prior.body_held[0].mass);
  EXPECT_GT(with_prior.bodies[0].mass, 0.2 * model.BodyInertia(0, x).mass());
  EXPECT_LT(with_prior.effective_parameters, model.num_parameters() - 1.0);
  EXPECT_GT(with_prior.effective_parameters, 1.0);
  // Covariance of x: symmetric, positive semi-definite.
  EXPECT_LT((with_prior.covariance - with_prior.covariance.transpose()).norm(), 1e-12 * with_prior.covariance.norm());
  EXPECT_GT(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(with_prior.covariance).eigenvalues().minCoeff(),
            -1e-12 * with_prior.covariance.norm());
}

// A payload reported in its link's frame (rotated and offset from the tree body's): the map L gives
// exactly RobotDynamics::BodyInertia, the payload's stds are UncertaintyOf(L J_pi_theta C_theta
// J_pi_theta^T L^T), and its mass std is the same as in the tree body's frame.
TEST(FitUncertainty, ReportFrameMapGivesTheBodyInItsReportFrame) {
  Rng rng(56);
  const Matrix3 R_BL = rng.Rotation();
  const Vector3 p_BL(0.03, -0.02, -0.3);
  const LinkResolver tool = [&](const std::string& link, LinkLocation* where) {
    if (link != "tool") return false;
    where->body = 2;
    where->link_in_body.R_AB = R_BL;
    where->link_in_body.p_AB = p_BL;
    return true;
  };
  const RobotDynamics model(Leg(), kJoints, ParseEffectList("payload@tool:mass=0.8,viscous"), tool);
  ASSERT_EQ(model.bodies().size(), 4u);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(model.num_parameters());
  for (int i = 0; i < 40; ++i) x[i] = rng.Uniform(-0.2, 0.2);
  const EstimatedBody& payload = model.bodies()[3];
  const Matrix10 L = ReportFrameMap(payload);
  const Vector10 in_report = L * payload.map.ToPi(x.segment<10>(30));
  EXPECT_LT((in_report - model.BodyInertia(3, x).vector()).norm(), 1e-14 * in_report.norm());
  // The prior, in the link frame, is the 0.8 kg sphere at the link origin.
  const Vector10 prior_in_link = L * payload.prior.vector();
  EXPECT_NEAR(prior_in_link[pi_index::kMass], 0.8, 1e-14);
  EXPECT_LT(prior_in_link.segment<3>(pi_index::kHx).norm(), 1e-14);

  const JointNormalEquations eq = AccumulateNormalEquations(model, ExciteLeg(model, x, 600, 0.005, 0.1, rng));
  const FitUncertainty u = EstimateFitUncertainty(model, eq, x, 1e-2);
  Matrix10 J_pi_theta;
  payload.map.ToPi(x.segment<10>(30), &J_pi_theta);
  const Matrix10 C_theta = u.covariance.block<10, 10>(30, 30);
  const BodyUncertainty expected = UncertaintyOf(model.BodyInertia(3, x), L * J_pi_theta * C_theta * J_pi_theta.transpose() * L.transpose());
  // The covariance's own stds (bodies_from_fit: without the CAD spread's floor that a quantity
  // held by the prior reports, which can only raise them).
  const BodyUncertainty& fit = u.bodies_from_fit[3];
  EXPECT_NEAR(fit.mass, expected.mass, 1e-12 * expected.mass);
  EXPECT_LT((fit.com - expected.com).norm(), 1e-12 * expected.com.norm());
  EXPECT_LT((fit.inertia_about_com - expected.inertia_about_com).norm(), 1e-12 * expected.inertia_about_com.norm());
  EXPECT_GE(u.bodies[3].mass, fit.mass);
  for (int k = 0; k < 3; ++k) EXPECT_GE(u.bodies[3].com[k], fit.com[k]);
  // The mass std does not depend on the frame.
  Matrix10 J_tree;
  payload.map.ToPi(x.segment<10>(30), &J_tree);
  EXPECT_NEAR(fit.mass, std::sqrt((J_tree * C_theta * J_tree.transpose())(0, 0)), 1e-12 * fit.mass);
}

// The leg of MassOfTheFirstLinkIsHeldByThePriorOrUndetermined: a truth inside the links' regions
// (so that the region barrier is idle), viscous friction 0.3, and its excitation with noise.
struct LegFit {
  RobotDynamics model = LegModel("viscous");
  Eigen::VectorXd x_true;
  JointSamples samples;
  JointNormalEquations eq;
  Eigen::VectorXd x;  ///< the fit with the paper's prior
};

Eigen::VectorXd LegTruth(const RobotDynamics& model, Rng& rng) {
  Eigen::VectorXd x_true = Eigen::VectorXd::Zero(model.num_parameters());
  for (int i = 0; i < 30; ++i) x_true[i] = rng.Uniform(-0.2, 0.2);
  for (int e = 0; e < 3; ++e) {
    x_true.segment<10>(10 * e) = ShrinkIntoRegion(model.bodies()[e].map, *model.bodies()[e].region, x_true.segment<10>(10 * e));
  }
  for (const EffectTerm& t : model.effects()) x_true[t.first_parameter] = std::log(0.3);
  return x_true;
}

LegFit FitLeg(std::uint64_t seed) {
  Rng rng(seed);
  LegFit f;
  f.x_true = LegTruth(f.model, rng);
  f.samples = ExciteLeg(f.model, f.x_true, 1500, 0.005, 0.2, rng);
  f.eq = AccumulateNormalEquations(f.model, f.samples);
  JointIdentificationOptions options;
  options.initial = f.x_true;
  f.x = IdentifyJointModel(f.model, f.eq, options).x;
  return f;
}

// The coefficients' covariance is x's pushed through J_w: in each body's block it is the body's
// pi covariance (brought to the report frame by L), and a viscous coefficient's variance is the
// effect's reported one; without time blocks it splits exactly into the data's and the prior's
// parts, and a single coefficient's std from UncertaintyOfCombination is sqrt of its diagonal.
// With time blocks a single coefficient follows the quantities' rule (the larger data part): a
// body's mass (the same in every frame) has the std and the label the body reports for it, a
// viscous coefficient the effect's std.
TEST(FitUncertainty, CoefficientCovarianceIsTheParametersPushedThroughTheCoefficients) {
  const LegFit f = FitLeg(57);
  const RobotDynamics& model = f.model;
  const FitUncertainty u = EstimateFitUncertainty(model, f.eq, f.x, 1e-2);
  const CoefficientCovariance& c = u.coefficients;
  const int F = model.num_features();
  ASSERT_EQ(c.total.rows(), F);
  ASSERT_EQ(c.total.cols(), F);
  EXPECT_EQ(c.block_data.size(), 0);
  EXPECT_EQ(c.undetermined_moves.cols(), 0);
  EXPECT_TRUE(c.prior_acts);
  EXPECT_LT((c.total - c.data - c.prior).norm(), 1e-9 * c.total.norm());
  for (int e = 0; e < 3; ++e) {
    const Matrix10 L = ReportFrameMap(model.bodies()[e]);
    const int b = 10 * model.bodies()[e].block;
    const Matrix10 expected = u.body_pi_covariance[e];
    EXPECT_LT((L * c.total.block<10, 10>(b, b) * L.transpose() - expected).norm(), 1e-9 * expected.norm()) << e;
  }
  for (int k = 0; k < 3; ++k) {
    const int f_b = model.effects()[k].first_feature;
    EXPECT_NEAR(std::sqrt(c.total(f_b, f_b)), u.effects[k][0], 1e-9 * u.effects[k][0]) << k;
    const CombinationUncertainty one = UncertaintyOfCombination(c, Eigen::VectorXd::Unit(F, f_b));
    EXPECT_NEAR(one.std, u.effects[k][0], 1e-9 * u.effects[k][0]) << k;
    EXPECT_FALSE(one.held_by_prior);  // no prior acts on an effect
  }
  const FitUncertainty blocked =
      EstimateFitUncertainty(model, f.eq, f.x, 1e-2, {}, AccumulateTimeBlocks(model, f.samples, f.x));
  ASSERT_GE(blocked.time_blocks, 20);
  ASSERT_EQ(blocked.coefficients.block_data.rows(), F);
  int held = 0;
  for (int e = 0; e < 3; ++e) {
    const int mass = 10 * model.bodies()[e].block + pi_index::kMass;
    const CombinationUncertainty m = UncertaintyOfCombination(blocked.coefficients, Eigen::VectorXd::Unit(F, mass));
    EXPECT_NEAR(m.std, blocked.bodies_from_fit[e].mass, 1e-9 * m.std) << e;
    EXPECT_EQ(m.held_by_prior, blocked.body_held[e].mass) << e;
    held += m.held_by_prior;
  }
  // Every mass alone is held here: the ab/ad link's never moves the torques (it turns about a fixed
  // axis), the others' only in combinations (hip_link.hz - 0.34 knee_link.m, ...).
  EXPECT_EQ(held, 3);
  for (int k = 0; k < 3; ++k) {
    const int f_b = model.effects()[k].first_feature;
    const double sd = UncertaintyOfCombination(blocked.coefficients, Eigen::VectorXd::Unit(F, f_b)).std;
    EXPECT_NEAR(sd, blocked.effects[k][0], 1e-9 * sd) << k;
  }
  EXPECT_THROW(UncertaintyOfCombination(c, Eigen::VectorXd::Zero(F - 1)), std::invalid_argument);
  EXPECT_THROW(UncertaintyOfCombination(c, Eigen::VectorXd::Constant(F, std::nan(""))), std::invalid_argument);
}

// Without a prior the model of the torques is linear in w, and an identifiable combination k^T w
// (k in the row space of A) is estimable: its least-squares estimate has variance
// sigma^2 k^T (A^T A)^- k for any generalized inverse (Gauss-Markov; Searle, Linear Models, 1971,
// ch. 5), whatever parameterization x of w the fit uses. Every base combination's std is that,
// with sigma^2 from the residual and the rank, computed here from A^T A directly. The ab/ad link's
// mass (a zero column: that link turns about a fixed axis) is no combination: its std is infinite
// without the prior, finite and held by the prior with it, while the combinations are not held.
TEST(FitUncertainty, BaseCombinationStdWithoutPriorIsTheLeastSquaresOne) {
  const LegFit f = FitLeg(54);
  const RobotDynamics& model = f.model;
  const int F = model.num_features();
  const IdentifiabilityReport id = AnalyzeIdentifiability(f.eq.AtA, model.FeatureNames());
  ASSERT_GT(id.directions.size(), 0u);
  ASSERT_EQ(static_cast<int>(id.base_combinations.size()), id.rank);

  // (A^T A)^-: D (D A^T A D)^+ D with the eigenvalues the rank keeps (sigma above 1e-5 sigma_max).
  Eigen::VectorXd d(F);
  for (int k = 0; k < F; ++k) d[k] = f.eq.AtA(k, k) > 0 ? 1.0 / std::sqrt(f.eq.AtA(k, k)) : 0.0;
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(d.asDiagonal() * f.eq.AtA * d.asDiagonal());
  const Eigen::VectorXd lambda = eig.eigenvalues();
  Eigen::VectorXd inverse = Eigen::VectorXd::Zero(F);
  int kept = 0;
  for (int k = 0; k < F; ++k) {
    if (lambda[k] > 1e-10 * lambda.maxCoeff()) inverse[k] = 1.0 / lambda[k], ++kept;
  }
  ASSERT_EQ(kept, id.rank);
  const Eigen::MatrixXd AtA_g =
      d.asDiagonal() * eig.eigenvectors() * inverse.asDiagonal() * eig.eigenvectors().transpose() * d.asDiagonal();
  const Eigen::VectorXd w = model.Coefficients(f.x);
  const double rows = 3.0 * f.eq.num_samples;
  const double s = std::sqrt(SquaredError(f.eq, w) / (rows - id.rank));

  const FitUncertainty none = EstimateFitUncertainty(model, f.eq, f.x, 0.0);
  EXPECT_NEAR(none.effective_parameters, id.rank, 1e-6);
  EXPECT_GT(none.coefficients.undetermined_moves.cols(), 0);
  EXPECT_FALSE(none.coefficients.prior_acts);
  double worst = 0.0;
  for (const BaseCombination& c : id.base_combinations) {
    const Eigen::VectorXd k = c.Vector(F);
    const double expected = s * std::sqrt(k.dot(AtA_g * k));
    const CombinationUncertainty got = UncertaintyOfCombination(none.coefficients, k);
    ASSERT_TRUE(std::isfinite(got.std)) << c.text;
    EXPECT_NEAR(got.std, expected, 1e-6 * expected) << c.text;
    EXPECT_FALSE(got.held_by_prior) << c.text;
    worst = std::max(worst, std::abs(got.std / expected - 1.0));
  }
  std::cerr << id.base_combinations.size() << " combinations of " << F
            << " coefficients: std against s sqrt(k^T (A^T A)^- k) within a relative " << worst << "\n";
  const int mass = 10 * model.bodies()[0].block + pi_index::kMass;
  ASSERT_EQ(f.eq.AtA(mass, mass), 0.0);
  EXPECT_TRUE(std::isinf(UncertaintyOfCombination(none.coefficients, Eigen::VectorXd::Unit(F, mass)).std));

  const FitUncertainty with_prior = EstimateFitUncertainty(model, f.eq, f.x, 1e-2);
  const CombinationUncertainty held = UncertaintyOfCombination(with_prior.coefficients, Eigen::VectorXd::Unit(F, mass));
  EXPECT_TRUE(std::isfinite(held.std));
  EXPECT_TRUE(held.held_by_prior);
  EXPECT_NEAR(held.std, with_prior.bodies_from_fit[0].mass, 1e-9 * held.std);
  // The prior only adds information: H_data + H_prior >= H_data, so g^T (H_data + H_prior)^-1 g
  // <= g^T H_data^+ g for g in H_data's range (and s^2 is smaller with the prior's fewer effective
  // parameters).
  for (const BaseCombination& c : id.base_combinations) {
    const double with = UncertaintyOfCombination(with_prior.coefficients, c.Vector(F)).std;
    EXPECT_LE(with, UncertaintyOfCombination(none.coefficients, c.Vector(F)).std * (1 + 1e-9)) << c.text;
  }
}

// Monte Carlo with the paper's prior (what `inertial identify` reports): one trajectory of the
// leg, K torque-noise draws, a fit from the prior for each; the spread of each base combination's
// estimate k^T w(x) over the draws against the std reported from the first fit.
TEST(FitUncertainty, BaseCombinationStdMatchesTheSpreadOverNoiseDraws) {
  constexpr int kDraws = 400;
  constexpr double kSigma = 0.1;  // torque noise [N m]
  Rng rng(58);
  const RobotDynamics model = LegModel("viscous");
  const Eigen::VectorXd x_true = LegTruth(model, rng);
  const JointSamples clean = ExciteLeg(model, x_true, 1500, 0.005, 0.0, rng);
  const int n = 3, F = model.num_features(), N = clean.size();
  Eigen::MatrixXd A(N * n, F);
  for (int j = 0; j < N; ++j) {
    model.Features(clean.q.row(j).transpose(), clean.qd.row(j).transpose(), clean.qdd.row(j).transpose(),
                   A.middleRows(j * n, n));
  }
  const Eigen::MatrixXd tau_by_sample = clean.tau.transpose();
  const Eigen::VectorXd tau_clean = Eigen::Map<const Eigen::VectorXd>(tau_by_sample.data(), tau_by_sample.size());
  JointNormalEquations eq;
  eq.AtA = A.transpose() * A;
  eq.num_samples = N;
  const IdentifiabilityReport id = AnalyzeIdentifiability(eq.AtA, model.FeatureNames());
  const int R = static_cast<int>(id.base_combinations.size());
  ASSERT_GT(R, 5);
  Eigen::MatrixXd K(R, F);
  for (int i = 0; i < R; ++i) K.row(i) = id.base_combinations[i].Vector(F).transpose();

  const JointIdentificationOptions options;
  Eigen::MatrixXd estimates(R, kDraws);
  FitUncertainty reported;
  for (int k = 0; k < kDraws; ++k) {
    Eigen::VectorXd tau = tau_clean;
    for (int i = 0; i < tau.size(); ++i) tau[i] += kSigma * rng.Normal();
    eq.Atb = A.transpose() * tau;
    eq.btb = tau.squaredNorm();
    const JointIdentificationResult fit = IdentifyJointModel(model, eq, options);
    ASSERT_TRUE(fit.lm.converged()) << "draw " << k << ": " << ToString(fit.lm.reason);
    estimates.col(k) = K * model.Coefficients(fit.x);
    if (k == 0) reported = EstimateFitUncertainty(model, eq, fit.x, options.prior_weight);
  }
  // (K-1) S^2 / sigma_q^2 ~ chi^2_{K-1}: S / sigma_q has standard error 1 / sqrt(2 (K-1)) = 0.035.
  // To first order the spread's variance is the data's part v_data of the reported variance
  // (fit_uncertainty.hpp), so spread / std = sqrt(v_data / v) (1 +- 4 se), held combinations
  // (v_data < v / 2) included. Gauss-Newton's dropped curvature moves the reported std by up to
  // 10 % for data-determined quantities (the file comment's Accuracy): that factor on each side.
  // (Measured when written: spread / sqrt(v_data) in [0.87, 1.05]; 3 of the 20, the knee's
  // Ixx - Izz, Ixy and Ixz, held: the light knee's inertias barely move the torques.)
  const double se = 1.0 / std::sqrt(2.0 * (kDraws - 1));
  int held = 0;
  double min_ratio = 1e300, max_ratio = 0.0;
  for (int i = 0; i < R; ++i) {
    const Eigen::VectorXd k = K.row(i).transpose();
    const std::string& text = id.base_combinations[i].text;
    const CombinationUncertainty u = UncertaintyOfCombination(reported.coefficients, k);
    ASSERT_TRUE(std::isfinite(u.std)) << text;
    const double expected = std::sqrt(k.dot(reported.coefficients.data * k)) / u.std;  // sqrt(v_data / v)
    const Eigen::VectorXd e = estimates.row(i).transpose();
    const double ratio = std::sqrt((e.array() - e.mean()).square().sum() / (kDraws - 1)) / u.std / expected;
    EXPECT_EQ(u.held_by_prior, expected * expected < 0.5) << text;
    EXPECT_LE(ratio, (1.0 + 4.0 * se) * 1.1) << text << ": spread / std " << ratio * expected << ", expected " << expected;
    EXPECT_GE(ratio, (1.0 - 4.0 * se) / 1.1) << text << ": spread / std " << ratio * expected << ", expected " << expected;
    held += u.held_by_prior;
    min_ratio = std::min(min_ratio, ratio);
    max_ratio = std::max(max_ratio, ratio);
  }
  std::cerr << R << " base combinations (" << held << " held by the prior) over " << kDraws
            << " draws: spread / sqrt(v_data) in [" << min_ratio << ", " << max_ratio << "] (band ["
            << (1.0 - 4.0 * se) / 1.1 << ", " << (1.0 + 4.0 * se) * 1.1 << "])\n";
}

TEST(FitUncertainty, RejectsInputsThatDoNotMatchTheModel) {
  Rng rng(55);
  const RobotDynamics model = LegModel("viscous");
  const Eigen::VectorXd x = Eigen::VectorXd::Zero(model.num_parameters());
  const JointNormalEquations eq = AccumulateNormalEquations(model, ExciteLeg(model, x, 50, 0.005, 0.1, rng));
  EXPECT_THROW(EstimateFitUncertainty(model, eq, x.head(5), 0.01), std::invalid_argument);
  EXPECT_THROW(EstimateFitUncertainty(model, eq, x, -1.0), std::invalid_argument);
  EXPECT_THROW(EstimateFitUncertainty(model, eq, x, 0.01, {true}), std::invalid_argument);
  JointNormalEquations few = eq;
  few.num_samples = 2;  // 6 torque rows for (without a prior) as many effective parameters as H_data's rank
  EXPECT_THROW(EstimateFitUncertainty(model, few, x, 0.0), std::invalid_argument);
}

}  // namespace
}  // namespace inertial
