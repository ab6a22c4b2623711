// The torques of one body (body_torques.hpp) against the recursive Newton-Euler inverse dynamics of
// the leg with that body added to its link by hand, minus that of the leg without it: a 2.8 kg box
// off the shank's origin, rotated, at seeded random states.
#include "inertial/model/body_torques.hpp"

#include <gtest/gtest.h>

#include "estimation/leg_chain.hpp"
#include "inertial/inertia/closed_form_bodies.hpp"
#include "test_support.hpp"

namespace inertial {
namespace {

TEST(BodyTorques, AKnownPayloadAgainstTheLegWithItAddedByHand) {
  const KinematicTree legs = testing::LegChain(testing::LegPriorLinks());
  const LinkResolver shank = [](const std::string& link, LinkLocation* at) {
    if (link != "shank") return false;
    at->body = 2;
    return true;
  };
  testing::Rng rng(38);
  const InertialParams box = SolidBox(2.8, 0.1, 0.06, 0.2, Pose{rng.Rotation(), Vector3(0.03, -0.02, -0.15)});
  std::vector<EffectSpec> effects = ParseEffectList("payload@shank");
  effects[0].inertia = box;
  const RobotDynamics model(legs, testing::kLegJoints, effects, shank);
  KinematicTree by_hand;
  for (int i = 0; i < legs.num_bodies(); ++i) {
    by_hand.AddBody(legs.body_name(i), legs.parent(i), legs.joint(i), i == 2 ? legs.inertia(i) + box : legs.inertia(i));
  }
  JointSamples data;
  const int N = 20;
  data.t = Eigen::VectorXd::LinSpaced(N, 0.0, 1.0);
  data.q = data.qd = data.qdd = data.tau = Eigen::MatrixXd::Zero(N, 3);
  for (int i = 0; i < N; ++i) {
    for (int j = 0; j < 3; ++j) {
      data.q(i, j) = rng.Uniform(-1.5, 1.5);
      data.qd(i, j) = rng.Uniform(-2.0, 2.0);
      data.qdd(i, j) = rng.Uniform(-5.0, 5.0);
    }
  }
  const Eigen::MatrixXd tau = BodyTorques(model, 3, data);  // the legs' three links, then the payload
  ASSERT_EQ(tau.rows(), N);
  for (int i = 0; i < N; ++i) {
    const Eigen::VectorXd q = data.q.row(i), qd = data.qd.row(i), qdd = data.qdd.row(i);
    const Eigen::VectorXd expected = by_hand.InverseDynamics(q, qd, qdd) - legs.InverseDynamics(q, qd, qdd);
    EXPECT_LT((tau.row(i).transpose() - expected).norm(), 1e-10 * (1.0 + expected.norm())) << i;
  }
  EXPECT_GT(tau.cwiseAbs().maxCoeff(), 1.0);  // a payload that matters (its weight on a lever)
  EXPECT_THROW(BodyTorques(model, 4, data), std::invalid_argument);
}

}  // namespace
}  // namespace inertial
