// The names of a robot estimator's state entries for a model known by its parameter names: the
// reference is the smaller model itself, built independently (its ParameterNames(), or its
// FeatureNames() for linear RLS), named through a larger model with payloads, rotors and effects.
#include "inertial/estimation/online/state_entry_names.hpp"

#include <gtest/gtest.h>

#include "estimation/leg_chain.hpp"

namespace inertial {
namespace {

// The chain's links by name, at their own frames (payloads sit at the link frame origin).
LinkResolver LegLinks() {
  return [](const std::string& link, LinkLocation* where) {
    for (int i = 0; i < 3; ++i) {
      if (link == testing::kLegJoints[static_cast<size_t>(i)] + "_link") {
        where->body = i;
        where->link_in_body = SpatialTransform();
        return true;
      }
    }
    return false;
  };
}

RobotDynamics Leg(const std::string& effects) {
  return RobotDynamics(testing::LegChain(testing::LegPriorLinks()), testing::kLegJoints,
                       effects.empty() ? std::vector<EffectSpec>{} : ParseEffectList(effects), LegLinks());
}

TEST(StateEntryNames, OfTheModelItselfAreItsParameterOrFeatureNames) {
  const RobotDynamics model = Leg("rotor@hip:gear=6,payload@knee_link,coulomb@knee,spring@hip,asymmetric@abad");
  std::string why;
  EXPECT_EQ(*StateEntryNames(model, EstimatorKind::kGaussNewton, model.ParameterNames(), &why), model.ParameterNames());
  EXPECT_EQ(*StateEntryNames(model, EstimatorKind::kGradient, model.ParameterNames(), &why), model.ParameterNames());
  EXPECT_EQ(*StateEntryNames(model, EstimatorKind::kLinearRls, model.ParameterNames(), &why), model.FeatureNames());
}

TEST(StateEntryNames, OfASmallerModelAreThatModelsNames) {
  const RobotDynamics large = Leg("rotor@hip:gear=6,payload@knee_link,coulomb@knee,viscous,spring@hip");
  for (const std::string smaller : {"", "rotor@hip:gear=6", "payload@knee_link", "viscous", "rotor@hip:gear=6,coulomb@knee,spring@hip",
                                    "payload@knee_link,viscous,spring@hip"}) {
    const RobotDynamics small = Leg(smaller);
    std::string why;
    const auto gn = StateEntryNames(large, EstimatorKind::kGaussNewton, small.ParameterNames(), &why);
    ASSERT_TRUE(gn) << smaller << ": " << why;
    EXPECT_EQ(*gn, small.ParameterNames()) << smaller;
    const auto linear = StateEntryNames(large, EstimatorKind::kLinearRls, small.ParameterNames(), &why);
    ASSERT_TRUE(linear) << smaller << ": " << why;
    EXPECT_EQ(*linear, small.FeatureNames()) << smaller;
  }
}

TEST(StateEntryNames, NamesEveryParameterTheModelLacks) {
  const RobotDynamics links = Leg("");
  const RobotDynamics with = Leg("coulomb@knee,viscous@hip");
  for (const EstimatorKind kind : {EstimatorKind::kGaussNewton, EstimatorKind::kLinearRls}) {
    std::string why;
    EXPECT_FALSE(StateEntryNames(links, kind, with.ParameterNames(), &why));
    EXPECT_EQ(why, "this model has no parameter 'coulomb@knee.log_bc', 'viscous@hip.log_b'");
  }
}

}  // namespace
}  // namespace inertial
