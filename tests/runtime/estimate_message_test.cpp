// The estimate sink's message (estimate_message.hpp), decoded by lcm-gen's own estimate_t: at the
// start of an estimate every body is its prior (the leg's closed-form boxes and cylinder: pi, mass,
// COM, and the triangle margin 2 min(L) worked by hand for the 1.8 kg box), theta is zero, the
// effect is b = e^s = 2 named by its feature, channels and residual RMS (padded with zeros) are
// the model's, the counters split into accepted, dropped and rejected by reason; linear RLS sends no
// theta and no standard deviations; a single body's message has the wrench channels; and the
// checkpoint description lists the joints and every parameter.
#include "inertial/runtime/estimate_message.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include "estimation/leg_chain.hpp"
#include "inertial/estimate_t.hpp"
#include "inertial/inertia/closed_form_bodies.hpp"
#include "test_support.hpp"

namespace inertial {
namespace {

inertial::estimate_t Decode(const std::vector<std::uint8_t>& bytes) {
  inertial::estimate_t m;
  EXPECT_EQ(m.decode(bytes.data(), 0, static_cast<int>(bytes.size())), static_cast<int>(bytes.size()));
  return m;
}

RobotDynamics LegWithViscousKnee() {
  return RobotDynamics(testing::LegChain(testing::LegPriorLinks()), testing::kLegJoints,
                       ParseEffectList("viscous@knee"), testing::NoLinks());
}

// 10 received: 6 accepted, 1 dropped by the queue, 2 that did not decode, 1 outlier.
SampleCounters Counters() {
  SampleCounters c;
  c.received = 10;
  c.accepted = 6;
  c.Reject(Rejection::kQueueFull);
  c.Reject(Rejection::kDecode, 2);
  c.Reject(Rejection::kOutlier);
  return c;
}

TEST(EstimateMessage, RobotEstimateAtItsPriors) {
  const RobotDynamics model = LegWithViscousKnee();
  Eigen::VectorXd x0 = Eigen::VectorXd::Zero(model.num_parameters());
  x0[model.effects()[0].first_parameter] = std::log(2.0);
  OnlineEstimatorOptions o;
  o.kind = EstimatorKind::kEkf;  // a covariance before any sample: the Kalman estimator's prior
  const OnlineJointEstimator est(model, x0, o);
  const inertial::estimate_t m = Decode(EncodeEstimate(est, 123456789, Eigen::Vector2d(0.1, 0.2), 0.5, Counters()));
  EXPECT_EQ(m.utime, 123456789);
  EXPECT_EQ(m.estimator, "ekf");
  ASSERT_EQ(m.num_bodies, 3);
  const std::vector<InertialParams> priors = testing::LegPriorLinks();
  for (int e = 0; e < 3; ++e) {
    const inertial::body_estimate_t& b = m.bodies[e];
    EXPECT_EQ(b.name, testing::kLegJoints[e] + "_link");
    for (int i = 0; i < 10; ++i) {
      EXPECT_NEAR(b.pi[i], priors[e].vector()[i], 1e-12) << e << " " << i;
      EXPECT_EQ(b.theta[i], 0.0);
    }
    EXPECT_NEAR(b.mass, priors[e].mass(), 1e-12);
    EXPECT_TRUE(b.physically_consistent);
    EXPECT_GT(b.mass_std, 0.0);
    EXPECT_GT(b.min_pseudo_inertia_eigenvalue, 0.0);
  }
  // The abad box: 1.8 kg, 0.12 x 0.08 x 0.08 m, COM (0, 0.04, 0). Ixx = 1.8 (0.08^2 + 0.08^2) / 12 =
  // 0.00192, Iyy = Izz = 1.8 (0.12^2 + 0.08^2) / 12 = 0.00312: margin Ixx + Iyy - Izz = 0.00192.
  EXPECT_NEAR(m.bodies[0].com[1], 0.04, 1e-15);
  EXPECT_NEAR(m.bodies[0].com[0], 0.0, 1e-15);
  EXPECT_NEAR(m.bodies[0].min_triangle_margin, 0.00192, 1e-12);
  ASSERT_EQ(m.num_effects, 1);
  EXPECT_EQ(m.effect_names[0], "viscous@knee.b");
  EXPECT_NEAR(m.effect_values[0], 2.0, 1e-12);
  EXPECT_EQ(m.channel_names, testing::kLegJoints);
  EXPECT_EQ(m.residual_rms, (std::vector<double>{0.1, 0.2, 0.0}));
  EXPECT_EQ(m.residual_window, 0.5);
  EXPECT_EQ(m.received, 10);
  EXPECT_EQ(m.accepted, 6);
  EXPECT_EQ(m.dropped, 1);
  EXPECT_EQ(m.rejected, 3);
  EXPECT_EQ(m.num_reasons, 2);
  EXPECT_EQ(m.reject_reasons, (std::vector<std::string>{"decode", "outlier"}));
  EXPECT_EQ(m.reject_counts, (std::vector<std::int64_t>{2, 1}));
}

TEST(EstimateMessage, LinearRlsSendsNoThetaAndNoStandardDeviations) {
  const RobotDynamics model = LegWithViscousKnee();
  OnlineEstimatorOptions o;
  o.kind = EstimatorKind::kLinearRls;
  const OnlineJointEstimator est(model, Eigen::VectorXd::Zero(model.num_parameters()), o);
  const inertial::estimate_t m = Decode(EncodeEstimate(est, 1, Eigen::VectorXd(), 1.0, SampleCounters()));
  EXPECT_EQ(m.estimator, "linear_rls");
  const std::vector<InertialParams> priors = testing::LegPriorLinks();
  for (int e = 0; e < 3; ++e) {
    EXPECT_NEAR(m.bodies[e].mass, priors[e].mass(), 1e-12);
    EXPECT_EQ(m.bodies[e].mass_std, 0.0);
    for (int i = 0; i < 10; ++i) EXPECT_EQ(m.bodies[e].theta[i], 0.0);
  }
  EXPECT_NEAR(m.effect_values[0], 1.0, 1e-12);  // b = e^0
  EXPECT_EQ(m.residual_rms, (std::vector<double>{0.0, 0.0, 0.0}));
  EXPECT_EQ(m.num_reasons, 0);
  EXPECT_EQ(m.rejected, 0);
}

TEST(EstimateMessage, SingleBodyEstimate) {
  const InertialParams prior = SolidCylinder(1.2, 0.05, 0.2);
  const OnlineBodyEstimator est(prior);
  Eigen::VectorXd rms(6);
  rms << 1, 2, 3, 4, 5, 6;
  const inertial::estimate_t m = Decode(EncodeBodyEstimate(est, "payload", 42, rms, 2.0, Counters()));
  EXPECT_EQ(m.utime, 42);
  ASSERT_EQ(m.num_bodies, 1);
  EXPECT_EQ(m.bodies[0].name, "payload");
  EXPECT_NEAR(m.bodies[0].mass, 1.2, 1e-12);
  for (int i = 0; i < 10; ++i) EXPECT_NEAR(m.bodies[0].pi[i], prior.vector()[i], 1e-12);
  EXPECT_GT(m.bodies[0].mass_std, 0.0);
  EXPECT_EQ(m.num_effects, 0);
  EXPECT_EQ(m.channel_names, (std::vector<std::string>{"mx", "my", "mz", "fx", "fy", "fz"}));
  EXPECT_EQ(m.residual_rms, (std::vector<double>{1, 2, 3, 4, 5, 6}));
  EXPECT_EQ(m.residual_window, 2.0);
  EXPECT_EQ(m.dropped, 1);
}

TEST(EstimateMessage, CheckpointDescriptionListsJointsAndParameters) {
  const RobotDynamics model = LegWithViscousKnee();
  OnlineEstimatorOptions o;
  o.kind = EstimatorKind::kGradient;
  OnlineJointEstimator est(model, Eigen::VectorXd::Zero(model.num_parameters()), o);
  const std::string d = CheckpointDescription(est);
  const std::string head = "gradient estimator; joints abad hip knee; parameters abad_link.alpha abad_link.d1 ";
  EXPECT_EQ(d.rfind(head, 0), 0u) << d;
  EXPECT_EQ(d.substr(d.size() - std::string(" knee_link.t3 viscous@knee.log_b").size()),
            " knee_link.t3 viscous@knee.log_b");
  // 3 x 10 theta entries and one effect parameter.
  std::istringstream words(d.substr(d.find("parameters ") + 11));
  int count = 0;
  for (std::string w; words >> w;) ++count;
  EXPECT_EQ(count, 31);

  SamplePipeline pipeline(&est, 20.0, 0.5);
  EXPECT_EQ(CheckpointDescription(pipeline), d);
  const inertial::estimate_t m = Decode(EncodeEstimate(pipeline, 7, Counters()));
  EXPECT_EQ(m.estimator, "gradient");
  EXPECT_EQ(m.residual_window, 0.5);
  EXPECT_EQ(m.residual_rms, (std::vector<double>{0.0, 0.0, 0.0}));  // nothing seen yet
  EXPECT_EQ(m.lost, 0);  // replay's: nothing lost before it
  // The daemon's samples lost before it (gaps in the time stamps), apart from dropped.
  const inertial::estimate_t lost = Decode(EncodeEstimate(pipeline, 7, Counters(), {}, 42));
  EXPECT_EQ(lost.lost, 42);
  EXPECT_EQ(lost.dropped, m.dropped);

  OnlineBodyEstimator body(SolidCylinder(1.0, 0.05, 0.2));
  SamplePipeline body_pipeline(&body, 0.5);
  EXPECT_EQ(CheckpointDescription(body_pipeline), "gauss_newton estimator; single body");
  EXPECT_EQ(Decode(EncodeEstimate(body_pipeline, 7, Counters(), {}, 3)).lost, 3);
}

}  // namespace
}  // namespace inertial
