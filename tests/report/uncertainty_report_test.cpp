// How sure each number is (uncertainty_report.hpp): the held quantities' names, a body's line of
// text and its JSON against strings and numbers written out by hand (a 2 kg box, 0.3 x 0.2 x 0.1 m:
// Ixx = m (b^2 + c^2) / 12 ...); a batch fit's uncertainty passed through with its source; and an
// online estimator's: none for the gradient law, the effect's standard deviation b sd(s) of
// b = e^s from the initial uncertainty, the mass's first-order standard deviation against central
// differences of the mass in theta, linear RLS's straight from its covariance, and the model
// file's notes naming them.
#include "inertial/report/uncertainty_report.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "estimation/leg_chain.hpp"
#include "inertial/inertia/closed_form_bodies.hpp"
#include "test_support.hpp"

namespace inertial {
namespace {

RobotDynamics LegWithViscousKnee() {
  return RobotDynamics(testing::LegChain(testing::LegPriorLinks()), testing::kLegJoints,
                       ParseEffectList("viscous@knee"), testing::NoLinks());
}

TEST(UncertaintyReport, HeldQuantitiesAreNamed) {
  BodyHeldByPrior held;
  EXPECT_TRUE(HeldQuantities(held).empty());
  held.mass = true;
  held.com[1] = true;
  held.inertia_about_com[2] = true;
  held.inertia_about_com[5] = true;
  EXPECT_EQ(HeldQuantities(held), (std::vector<std::string>{"mass", "com.y", "Izz", "Ixz"}));
}

TEST(UncertaintyReport, BodyTextAndJsonByHand) {
  // 2 kg box of 0.3 x 0.2 x 0.1 m with its COM at (0.1, 0, 0): Ixx = 2 (0.04 + 0.01) / 12 = 0.00833,
  // Iyy = 2 (0.09 + 0.01) / 12 = 0.0167, Izz = 2 (0.09 + 0.04) / 12 = 0.0217, products 0.
  const InertialParams box = SolidBox(2.0, 0.3, 0.2, 0.1, Pose{Matrix3::Identity(), Vector3(0.1, 0, 0)});
  BodyUncertainty u;
  u.mass = 0.5;
  u.com = Vector3(0.01, 0.02, std::numeric_limits<double>::infinity());
  u.inertia_about_com << 1e-3, 2e-3, 3e-3, 4e-4, 5e-4, 6e-4;
  EXPECT_EQ(BodyUncertaintyText(box, u, nullptr),
            "mass 2 +- 0.5 kg, COM [0.1 0 0] +- [0.01 0.02 inf] m, inertia about COM [Ixx Iyy Izz Ixy Iyz Ixz] "
            "[0.00833 0.0167 0.0217 0 0 0] +- [0.001 0.002 0.003 0.0004 0.0005 0.0006] kg m^2");
  BodyHeldByPrior held;
  held.mass = true;
  held.com[2] = true;
  held.inertia_about_com[0] = true;
  const std::string text = BodyUncertaintyText(box, u, &held);
  EXPECT_NE(text.find("mass 2 +- 0.5 kg (held by the prior), COM"), std::string::npos) << text;
  EXPECT_NE(text.find("kg m^2; held by the prior (the data barely determine them): com.z, Ixx"), std::string::npos)
      << text;

  const nlohmann::json j = BodyUncertaintyJson(u, &held);
  EXPECT_EQ(j["mass_std"], 0.5);
  EXPECT_EQ(j["com_std"][1], 0.02);
  EXPECT_EQ(j["com_std"][2], "inf");
  EXPECT_EQ(j["inertia_about_com_std"][5], 6e-4);
  EXPECT_EQ(j["held_by_prior"], nlohmann::json({"mass", "com.z", "Ixx"}));
  EXPECT_EQ(BodyUncertaintyJson(u, nullptr)["held_by_prior"], nlohmann::json::array());
}

TEST(UncertaintyReport, FromFitKeepsTheFitsNumbers) {
  FitUncertainty fit;
  fit.noise_sigma = 0.0123456;
  fit.bodies.resize(2);
  fit.bodies[1].mass = 0.7;
  fit.body_held.resize(2);
  fit.body_held[0].mass = true;
  fit.effects = {{0.1, 0.2}};
  const ModelUncertainty u = FromFit(fit);
  ASSERT_EQ(u.bodies.size(), 2u);
  EXPECT_EQ(u.bodies[1].mass, 0.7);
  EXPECT_TRUE(u.held[0].mass);
  EXPECT_EQ(u.effects, fit.effects);
  EXPECT_EQ(u.source, "from the fit's curvature, torque noise 0.0123 N m estimated from the residual");
}

TEST(UncertaintyReport, GaussNewtonEstimatorsCovarianceByHand) {
  const RobotDynamics model = LegWithViscousKnee();
  // Start with the knee's b = e^s = 2; every effect parameter's initial std 0.2, theta's 0.3.
  Eigen::VectorXd x0 = Eigen::VectorXd::Zero(model.num_parameters());
  const int s = model.effects()[0].first_parameter;
  x0[s] = std::log(2.0);
  OnlineEstimatorOptions o;
  o.kind = EstimatorKind::kEkf;
  o.effect_std = 0.2;
  o.theta_std = 0.3;
  const OnlineJointEstimator est(model, x0, o);
  const std::optional<ModelUncertainty> u = FromOnlineEstimator(est);
  ASSERT_TRUE(u.has_value());
  EXPECT_EQ(u->source, "from the ekf estimator's covariance");
  ASSERT_EQ(u->effects.size(), 1u);
  ASSERT_EQ(u->effects[0].size(), 1u);
  EXPECT_NEAR(u->effects[0][0], 2.0 * 0.2, 1e-12);  // db = b ds
  ASSERT_EQ(u->bodies.size(), 3u);
  for (int e = 0; e < 3; ++e) {
    // The mass's first-order std: |d m / d theta| 0.3 (P = 0.3^2 I), d m / d theta by central differences.
    double g2 = 0.0;
    for (int k = 0; k < 10; ++k) {
      Eigen::VectorXd xp = x0, xm = x0;
      xp[10 * e + k] += 1e-6;
      xm[10 * e + k] -= 1e-6;
      const double g = (model.BodyInertia(e, xp).mass() - model.BodyInertia(e, xm).mass()) / 2e-6;
      g2 += g * g;
    }
    EXPECT_NEAR(u->bodies[e].mass, 0.3 * std::sqrt(g2), 1e-6 * std::sqrt(g2)) << e;
  }

  // The model file's notes: one per body and the effect, with the numbers above.
  const ModelSnapshot snapshot = SnapshotWithUncertainty(est);
  ASSERT_EQ(snapshot.notes.count("viscous@knee"), 1u);
  EXPECT_EQ(snapshot.notes.at("viscous@knee"),
            "standard deviations (from the ekf estimator's covariance): b = 2 +- 0.4 N m s/rad");
  ASSERT_EQ(snapshot.notes.count("knee_link"), 1u);
  EXPECT_EQ(snapshot.notes.at("knee_link").rfind("standard deviations (from the ekf estimator's covariance): "
                                                 "mass 0.5 +- ", 0), 0u)
      << snapshot.notes.at("knee_link");
}

TEST(UncertaintyReport, LinearRlsFromItsCovarianceAndNoneForTheGradientLaw) {
  const RobotDynamics model = LegWithViscousKnee();
  const Eigen::VectorXd x0 = Eigen::VectorXd::Zero(model.num_parameters());
  OnlineEstimatorOptions o;
  o.kind = EstimatorKind::kGradient;
  EXPECT_FALSE(FromOnlineEstimator(OnlineJointEstimator(model, x0, o)).has_value());
  // No standard deviations; only each link's plausibility (region_plausibility.hpp) is noted.
  for (const auto& [name, note] : SnapshotWithUncertainty(OnlineJointEstimator(model, x0, o)).notes) {
    EXPECT_EQ(note.find("standard deviations"), std::string::npos) << name << ": " << note;
    EXPECT_EQ(note.rfind("plausible: region from ", 0), 0u) << name << ": " << note;
  }

  // Linear RLS starts with std 0.3 (|w0| + 0.01) on each coefficient w: the mass's is 0.3 (m0 + 0.01)
  // and b's (w0 = e^0 = 1) is 0.3 (1 + 0.01).
  o.kind = EstimatorKind::kLinearRls;
  const OnlineJointEstimator rls(model, x0, o);
  const std::optional<ModelUncertainty> u = FromOnlineEstimator(rls);
  ASSERT_TRUE(u.has_value());
  const std::vector<InertialParams> priors = testing::LegPriorLinks();
  for (int e = 0; e < 3; ++e) EXPECT_NEAR(u->bodies[e].mass, 0.3 * (priors[e].mass() + 0.01), 1e-12) << e;
  EXPECT_NEAR(u->effects[0][0], 0.3 * 1.01, 1e-12);
}

}  // namespace
}  // namespace inertial
