#include "inertial/model/body_effect_model.hpp"

#include <gtest/gtest.h>

#include "inertial/inertia/closed_form_bodies.hpp"
#include "inertial/model/rigid_body_regressor.hpp"
#include "test_support.hpp"

namespace inertial {
namespace {

using testing::Rng;

BodyLog RandomLog(Rng& rng, int N, bool gravity) {
  BodyLog log;
  for (int i = 0; i < N; ++i) {
    TwistWrenchSample s;
    s.t = 0.01 * i + (i > 0 ? rng.Uniform(0, 0.002) : 0.0);
    s.twist = rng.UniformVector<6>(-2, 2);
    s.wrench = rng.UniformVector<6>(-3, 3);
    log.samples.push_back(s);
    if (gravity) log.gravity.push_back(rng.UniformVector<3>(-9.81, 9.81));
  }
  return log;
}

const std::vector<BodyEffectKind> kAll{BodyEffectKind::kForceBias, BodyEffectKind::kVelocityBias,
                                       BodyEffectKind::kMomentBias, BodyEffectKind::kGravity};

// The Jacobian of the predicted wrench with every effect is that of central differences.
TEST(BodyEffectModel, JacobianMatchesCentralDifferences) {
  Rng rng(3);
  const InertialParams prior = SolidBox(0.8, 0.2, 0.1, 0.3, rng.RandomPose<Pose>(0.2));
  const BodyEffectModel model(prior, kAll);
  ASSERT_EQ(model.num_parameters(), 10 + 3 + 6 + 3 + 3);
  for (bool gravity : {false, true}) {
    const BodyLog log = RandomLog(rng, 4, gravity);
    for (int trial = 0; trial < 5; ++trial) {
      Eigen::VectorXd x(model.num_parameters());
      for (int i = 0; i < x.size(); ++i) x[i] = rng.Uniform(-0.5, 0.5);
      for (int i = 0; i < log.num_pairs(); ++i) {
        Eigen::MatrixXd J;
        model.PredictPair(x, log, i, &J);
        Eigen::MatrixXd Jn(6, x.size());
        for (int k = 0; k < x.size(); ++k) {
          Eigen::VectorXd xp = x, xm = x;
          xp[k] += 1e-6;
          xm[k] -= 1e-6;
          Jn.col(k) = (model.PredictPair(xp, log, i) - model.PredictPair(xm, log, i)) / 2e-6;
        }
        EXPECT_LT(testing::RelativeError(J, Jn), 1e-7) << "pair " << i << " gravity " << gravity;
      }
    }
  }
}

// Independent forms: without effects the prediction is the paper's midpoint regressor times pi;
// with a velocity bias it is the regressor of the de-biased twists; with biases it adds them; an
// unmodelled gravity is the regressor with that gravity.
TEST(BodyEffectModel, EffectsAreWhatTheyClaim) {
  Rng rng(4);
  const InertialParams prior = SolidCylinder(1.2, 0.05, 0.2, rng.RandomPose<Pose>(0.1));
  const BodyLog log = RandomLog(rng, 6, true);
  const Vector10 theta = rng.UniformVector<10>(-0.3, 0.3);
  const BodyEffectModel plain(prior, {});
  Eigen::VectorXd x = theta;
  const Vector10 pi = plain.Body(x).vector();
  const Vector6 b_v = rng.UniformVector<6>(-0.2, 0.2);
  const Vector3 b_f = rng.UniformVector<3>(-1, 1), b_m = rng.UniformVector<3>(-1, 1), g_u = rng.UniformVector<3>(-2, 2);
  const BodyEffectModel full(prior, kAll);
  Eigen::VectorXd xf(full.num_parameters());
  xf << theta, b_f, b_v, b_m, g_u;
  for (int i = 0; i < log.num_pairs(); ++i) {
    TwistWrenchSample s0 = log.samples[i], s1 = log.samples[i + 1];
    Matrix6x10 Y;
    Vector6 w;
    MidpointRegressorPair(s0, s1, 0.5 * (log.gravity[i] + log.gravity[i + 1]), &Y, &w);
    EXPECT_LT((plain.PredictPair(x, log, i) - Y * pi).norm(), 1e-12 * (1 + (Y * pi).norm()));
    EXPECT_LT((BodyEffectModel::MeasuredPair(log, i) - w).norm(), 1e-14 * (1 + w.norm()));
    s0.twist -= b_v;
    s1.twist -= b_v;
    MidpointRegressorPair(s0, s1, 0.5 * (log.gravity[i] + log.gravity[i + 1]) + g_u, &Y, &w);
    Vector6 expected = Y * pi;
    expected.head<3>() += b_m;
    expected.tail<3>() += b_f;
    EXPECT_LT((full.PredictPair(xf, log, i) - expected).norm(), 1e-12 * (1 + expected.norm()));
  }
  EXPECT_EQ(full.EffectValues(1, xf), Eigen::VectorXd(b_v));
  EXPECT_EQ(full.ParameterNames()[13], "velocity_bias.wx");
}

TEST(BodyEffectModel, ParsesEffectLists) {
  EXPECT_EQ(ParseBodyEffectList("force_bias, velocity_bias").size(), 2u);
  EXPECT_TRUE(ParseBodyEffectList("").empty());
  EXPECT_THROW(ParseBodyEffectList("force_bias,force_bias"), std::invalid_argument);
  EXPECT_THROW(ParseBodyEffectList("coulomb"), std::invalid_argument);
  EXPECT_THROW(ParseBodyEffectList("force_bias,,gravity"), std::invalid_argument);
  EXPECT_THROW(BodyEffectModel(InertialParams(), {BodyEffectKind::kGravity, BodyEffectKind::kGravity}),
               std::invalid_argument);
}

}  // namespace
}  // namespace inertial
