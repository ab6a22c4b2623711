#include "inertial/model/robot_dynamics.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "inertial/inertia/closed_form_bodies.hpp"
#include "test_support.hpp"

namespace inertial {
namespace {

using testing::Rng;

// A 3-DOF chain (revolute x, revolute y, prismatic z) with random origins and inertias.
KinematicTree Chain(Rng& rng) {
  KinematicTree tree;
  const Vector3 axes[3] = {Vector3::UnitX(), Vector3::UnitY(), Vector3::UnitZ()};
  for (int i = 0; i < 3; ++i) {
    JointModel j;
    j.name = "j" + std::to_string(i);
    j.type = i == 2 ? JointType::kPrismatic : JointType::kRevolute;
    j.p_parent_joint = rng.UniformVector<3>(-0.3, 0.3);
    j.R_parent_joint = rng.Rotation();
    j.axis = axes[i];
    // One draw per statement, in the order the x86-64 build drew them (see testing::Rng).
    const Pose pose{rng.Rotation(), rng.UniformVector<3>(-0.2, 0.2)};
    const Vector3 L = rng.UniformVector<3>(1e-3, 0.03);
    const double mass = rng.Uniform(0.5, 3);
    const InertialParams body = BodyFromSecondMoments(mass, L, pose);
    tree.AddBody("l" + std::to_string(i), i - 1, j, body);
  }
  return tree;
}

LinkResolver ChainLinks(const SpatialTransform& tool_in_l2) {
  return [tool_in_l2](const std::string& link, LinkLocation* where) {
    if (link == "tool") {
      *where = LinkLocation{2, tool_in_l2};
      return true;
    }
    if (link == "base") {
      *where = LinkLocation{-1, SpatialTransform()};
      return true;
    }
    for (int i = 0; i < 3; ++i) {
      if (link == "l" + std::to_string(i)) {
        *where = LinkLocation{i, SpatialTransform()};
        return true;
      }
    }
    return false;
  };
}

const std::vector<std::string> kJoints = {"j0", "j1", "j2"};

// Without effects and at x = 0 (the prior), the model is the tree's own inverse dynamics.
TEST(RobotDynamics, PriorWithoutEffectsIsTheTreesInverseDynamics) {
  Rng rng(21);
  const KinematicTree tree = Chain(rng);
  const RobotDynamics model(tree, kJoints, {}, ChainLinks(SpatialTransform()));
  ASSERT_EQ(model.num_parameters(), 30);
  for (int trial = 0; trial < 20; ++trial) {
    const Eigen::VectorXd q = Eigen::VectorXd::NullaryExpr(3, [&] { return rng.Uniform(-2, 2); });
    const Eigen::VectorXd qd = Eigen::VectorXd::NullaryExpr(3, [&] { return rng.Uniform(-2, 2); });
    const Eigen::VectorXd qdd = Eigen::VectorXd::NullaryExpr(3, [&] { return rng.Uniform(-2, 2); });
    const Eigen::VectorXd expected = tree.InverseDynamics(q, qd, qdd);
    EXPECT_LT((model.InverseDynamics(Eigen::VectorXd::Zero(30), q, qd, qdd) - expected).norm(),
              1e-11 * (1 + expected.norm()));
  }
}

// Every joint effect against its formula written out by hand.
TEST(RobotDynamics, JointEffectsAddTheirTorques) {
  Rng rng(22);
  const KinematicTree tree = Chain(rng);
  const RobotDynamics model(tree, kJoints,
                            ParseEffectList("viscous@j0,coulomb@j1:scale=0.2,offset@j2,armature@j0,spring@j1"),
                            ChainLinks(SpatialTransform()));
  ASSERT_EQ(model.num_parameters(), 30 + 6);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(36);
  const double b = 0.7, bc = 1.3, c = -0.4, Ia = 0.05, k = 12.0, q0 = 0.3;
  x.tail<6>() << std::log(b), std::log(bc), c, std::log(Ia), std::log(k), q0;
  Eigen::VectorXd q(3), qd(3), qdd(3);
  q << 0.4, -0.9, 0.1;
  qd << 1.1, -0.05, 0.3;
  qdd << -2.0, 0.5, 1.5;
  Eigen::VectorXd expected = tree.InverseDynamics(q, qd, qdd);
  expected[0] += b * qd[0] + Ia * qdd[0];
  expected[1] += bc * std::tanh(qd[1] / 0.2) + k * (q[1] - q0);
  expected[2] += c;
  EXPECT_LT((model.InverseDynamics(x, q, qd, qdd) - expected).norm(), 1e-11 * (1 + expected.norm()));
  EXPECT_NEAR(model.EffectValues(4, x)[0], k, 1e-12);
  EXPECT_NEAR(model.EffectValues(4, x)[1], q0, 1e-12);
  // Round trip through the effect coefficients.
  const Eigen::VectorXd w = model.Coefficients(x);
  const Eigen::VectorXd x_back = model.ParametersFromEffectCoefficients(w.tail(6));
  EXPECT_LT((x_back.tail(6) - x.tail(6)).norm(), 1e-12);
}

// The friction shapes of real arms against their formulas: asymmetric Coulomb (one level per
// direction) and the sigmoid of Gaz et al. 2019 (eq. 8) written with exp, as the paper does.
TEST(RobotDynamics, FrictionShapesAddTheirTorques) {
  Rng rng(27);
  const KinematicTree tree = Chain(rng);
  const std::vector<EffectSpec> effects =
      ParseEffectList("asymmetric@j0:scale=0.05,sigmoid@j1:steepness=40:shift=-0.03,asymmetric@j2:scale=0.1");
  EXPECT_DOUBLE_EQ(effects[1].steepness, 40.0);
  EXPECT_DOUBLE_EQ(effects[1].shift, -0.03);
  const RobotDynamics model(tree, kJoints, effects, ChainLinks(SpatialTransform()));
  ASSERT_EQ(model.num_parameters(), 30 + 5);
  const double bp = 0.8, bn = 0.3, p1 = 1.7, bp2 = 0.2, bn2 = 0.9;
  Eigen::VectorXd x = Eigen::VectorXd::Zero(35);
  x.tail<5>() << std::log(bp), std::log(bn), std::log(p1), std::log(bp2), std::log(bn2);
  auto logistic = [](double z) { return 1.0 / (1.0 + std::exp(-z)); };
  for (int trial = 0; trial < 20; ++trial) {
    const Eigen::VectorXd q = Eigen::VectorXd::NullaryExpr(3, [&] { return rng.Uniform(-2, 2); });
    const Eigen::VectorXd qd = Eigen::VectorXd::NullaryExpr(3, [&] { return rng.Uniform(-0.3, 0.3); });
    const Eigen::VectorXd qdd = Eigen::VectorXd::NullaryExpr(3, [&] { return rng.Uniform(-2, 2); });
    Eigen::VectorXd expected = tree.InverseDynamics(q, qd, qdd);
    const double s0 = std::tanh(qd[0] / 0.05), s2 = std::tanh(qd[2] / 0.1);
    expected[0] += s0 > 0 ? bp * s0 : bn * s0;
    expected[1] += p1 * logistic(40.0 * (qd[1] - 0.03)) - p1 * logistic(40.0 * -0.03);
    expected[2] += s2 > 0 ? bp2 * s2 : bn2 * s2;
    EXPECT_LT((model.InverseDynamics(x, q, qd, qdd) - expected).norm(), 1e-11 * (1 + expected.norm()));
    for (int k = 0; k < 3; ++k) {
      const ModelEffect m{effects[k], model.EffectValues(k, x)};
      const double alone = k == 0 ? (s0 > 0 ? bp * s0 : bn * s0)
                           : k == 1 ? p1 * (logistic(40.0 * (qd[1] - 0.03)) - logistic(-1.2))
                                    : (s2 > 0 ? bp2 * s2 : bn2 * s2);
      EXPECT_NEAR(VelocityEffectTorque(m.spec, m.values, qd[k]), alone, 1e-12);
    }
  }
  EXPECT_NEAR(model.EffectValues(0, x)[1], bn, 1e-12);
  EXPECT_NEAR(model.EffectValues(1, x)[0], p1, 1e-12);
  // Zero friction at rest, and the sigmoid's two levels: p1 (1 - S(p2 p3)) and -p1 S(p2 p3).
  EXPECT_EQ(SigmoidFriction(0.0, 40.0, -0.03), 0.0);
  EXPECT_NEAR(SigmoidFriction(1e3, 40.0, -0.03), 1.0 - logistic(-1.2), 1e-12);
  EXPECT_NEAR(SigmoidFriction(-1e3, 40.0, -0.03), -logistic(-1.2), 1e-12);
  // Round trips: coefficients, model-file values, and the --effects item.
  const Eigen::VectorXd w = model.Coefficients(x);
  EXPECT_LT((model.ParametersFromEffectCoefficients(w.tail(5)).tail(5) - x.tail(5)).norm(), 1e-12);
  std::vector<ModelEffect> values;
  for (int k = 0; k < 3; ++k) values.push_back({effects[k], model.EffectValues(k, x)});
  EXPECT_LT((model.ParametersFromEffectValues(values).tail(5) - x.tail(5)).norm(), 1e-12);
  for (const EffectSpec& e : effects) {
    const EffectSpec back = ParseEffectList(EffectItem(e)).at(0);
    EXPECT_EQ(back.kind, e.kind);
    EXPECT_EQ(back.target, e.target);
    EXPECT_DOUBLE_EQ(back.velocity_scale, e.velocity_scale);
    EXPECT_DOUBLE_EQ(back.steepness, e.steepness);
    EXPECT_DOUBLE_EQ(back.shift, e.shift);
  }
  values[0].values[1] = -0.1;
  EXPECT_THROW(model.ParametersFromEffectValues(values), std::invalid_argument);
}

// A payload on a link frame posed inside a body adds exactly its inertia to that body.
TEST(RobotDynamics, PayloadAddsItsInertiaToTheBody) {
  Rng rng(23);
  const KinematicTree tree = Chain(rng);
  SpatialTransform tool;
  tool.R_AB = rng.Rotation();
  tool.p_AB = Vector3(0.1, -0.05, 0.2);
  const RobotDynamics model(tree, kJoints, ParseEffectList("payload@tool:mass=1.5:radius=0.04"), ChainLinks(tool));
  ASSERT_EQ(model.num_parameters(), 40);
  // The same robot with the sphere added by hand to link 2, at the tool origin.
  KinematicTree by_hand;
  for (int i = 0; i < 3; ++i) {
    InertialParams I = tree.inertia(i);
    if (i == 2) I = I + SolidSphere(1.5, 0.04, Pose{Matrix3::Identity(), tool.p_AB});
    by_hand.AddBody(tree.body_name(i), tree.parent(i), tree.joint(i), I);
  }
  Eigen::VectorXd q(3), qd(3), qdd(3);
  q << 0.2, 0.8, -0.1;
  qd << -1.0, 0.4, 0.2;
  qdd << 0.3, -1.2, 2.0;
  const Eigen::VectorXd expected = by_hand.InverseDynamics(q, qd, qdd);
  EXPECT_LT((model.InverseDynamics(Eigen::VectorXd::Zero(40), q, qd, qdd) - expected).norm(), 1e-11 * (1 + expected.norm()));
  // Reported in the tool frame: a sphere at the origin.
  const InertialParams reported = model.BodyInertia(3, Eigen::VectorXd::Zero(40));
  EXPECT_NEAR(reported.mass(), 1.5, 1e-12);
  EXPECT_LT(reported.com().norm(), 1e-12);
}

// A rotor on j0 (axis x) with gear N adds N^2 Ir qdd0 when only j0 moves and the base is still.
TEST(RobotDynamics, RotorReflectsItsInertia) {
  Rng rng(24);
  const KinematicTree tree = Chain(rng);
  const RobotDynamics model(tree, kJoints, ParseEffectList("rotor@j0:gear=8:mass=0.2:radius=0.03:length=0.02"),
                            ChainLinks(SpatialTransform()));
  ASSERT_EQ(model.num_parameters(), 40);
  Eigen::VectorXd q = Eigen::VectorXd::Zero(3), qd = Eigen::VectorXd::Zero(3), qdd = Eigen::VectorXd::Zero(3);
  qdd[0] = 2.0;
  const double Ir = 0.5 * 0.2 * 0.03 * 0.03;
  const RobotDynamics without(tree, kJoints, {}, ChainLinks(SpatialTransform()));
  const Eigen::VectorXd extra = model.InverseDynamics(Eigen::VectorXd::Zero(40), q, qd, qdd) -
                                without.InverseDynamics(Eigen::VectorXd::Zero(30), q, qd, qdd);
  // Gravity acts on the rotor too but its COM is on the axis at the joint: no gravity torque on j0.
  EXPECT_NEAR(extra[0], 64.0 * Ir * 2.0, 1e-12);
}

// Two independent algorithms for tau: the regressor A(q, qd, qdd) w(x) (body wrenches linear in pi
// carried up the tree) and recursive Newton-Euler on the bodies of w plus the effect terms, with
// rotors, a payload and every joint-effect kind, at random parameters and states; and from
// coefficients that are not physically consistent (the map is linear in w).
TEST(RobotDynamics, NewtonEulerAgreesWithTheRegressor) {
  Rng rng(29);
  const KinematicTree tree = Chain(rng);
  SpatialTransform tool;
  tool.p_AB = Vector3(0.05, 0.1, -0.1);
  const RobotDynamics model(
      tree, kJoints,
      ParseEffectList("rotor@j0:gear=8,rotor@j1:gear=-5,payload@tool,viscous@j0,coulomb@j1:scale=0.2,offset@j2,"
                      "armature@j0,spring@j1,asymmetric@j2,sigmoid@j0"),
      ChainLinks(tool));
  Eigen::MatrixXd A(3, model.num_features());
  for (int trial = 0; trial < 20; ++trial) {
    const Eigen::VectorXd x = Eigen::VectorXd::NullaryExpr(model.num_parameters(), [&] { return rng.Uniform(-1, 1); });
    const Eigen::VectorXd q = Eigen::VectorXd::NullaryExpr(3, [&] { return rng.Uniform(-2, 2); });
    const Eigen::VectorXd qd = Eigen::VectorXd::NullaryExpr(3, [&] { return rng.Uniform(-2, 2); });
    const Eigen::VectorXd qdd = Eigen::VectorXd::NullaryExpr(3, [&] { return rng.Uniform(-2, 2); });
    model.Features(q, qd, qdd, A);
    const Eigen::VectorXd expected = A * model.Coefficients(x);
    EXPECT_LT((model.InverseDynamics(x, q, qd, qdd) - expected).norm(), 1e-12 * (1 + expected.norm())) << trial;
    const Eigen::VectorXd w = Eigen::VectorXd::NullaryExpr(model.num_features(), [&] { return rng.Uniform(-1, 1); });
    const Eigen::VectorXd expected_w = A * w;
    EXPECT_LT((model.InverseDynamicsFromCoefficients(w, q, qd, qdd) - expected_w).norm(),
              1e-12 * (1 + expected_w.norm()))
        << trial;
  }
  EXPECT_THROW(model.InverseDynamicsFromCoefficients(Eigen::VectorXd::Zero(3), Eigen::VectorXd::Zero(3),
                                                     Eigen::VectorXd::Zero(3), Eigen::VectorXd::Zero(3)),
               std::invalid_argument);
}

TEST(RobotDynamics, CoefficientJacobianMatchesFiniteDifferences) {
  Rng rng(25);
  const KinematicTree tree = Chain(rng);
  const RobotDynamics model(tree, kJoints, ParseEffectList("viscous,coulomb,offset,armature@j1,spring@j2,payload@tool,rotor@j1:gear=5,"
                                            "asymmetric@j0,sigmoid@j2:shift=0.01"),
                            ChainLinks(SpatialTransform()));
  const int n = model.num_parameters();
  const Eigen::VectorXd x = Eigen::VectorXd::NullaryExpr(n, [&] { return rng.Uniform(-0.5, 0.5); });
  Eigen::MatrixXd J;
  model.Coefficients(x, &J);
  const double h = 1e-6;
  for (int k = 0; k < n; ++k) {
    Eigen::VectorXd xp = x, xm = x;
    xp[k] += h;
    xm[k] -= h;
    const Eigen::VectorXd fd = (model.Coefficients(xp) - model.Coefficients(xm)) / (2 * h);
    EXPECT_LT((J.col(k) - fd).norm(), 1e-7 * (1 + fd.norm())) << model.ParameterNames()[k];
  }
  EXPECT_EQ(static_cast<int>(model.ParameterNames().size()), n);
  EXPECT_EQ(static_cast<int>(model.FeatureNames().size()), model.num_features());
}

TEST(RobotDynamics, RejectsEffectsThatDoNotFitTheRobot) {
  Rng rng(26);
  const KinematicTree tree = Chain(rng);
  auto message = [&](const std::string& effects) {
    try {
      RobotDynamics(tree, kJoints, ParseEffectList(effects), ChainLinks(SpatialTransform()));
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message("coulomb@knee").find("unknown joint 'knee' (joints: j0, j1, j2)"), std::string::npos);
  EXPECT_NE(message("viscous,viscous@j1").find("already in the list"), std::string::npos);
  EXPECT_NE(message("payload@nowhere").find("unknown link 'nowhere'"), std::string::npos);
  EXPECT_NE(message("payload@base").find("fixed to the base"), std::string::npos);
  EXPECT_NE(message("rotor@j2:gear=3").find("not revolute"), std::string::npos);
}

}  // namespace
}  // namespace inertial
