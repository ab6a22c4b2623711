// The effect catalog: the --effects syntax (kinds, targets, options, errors naming the item), the
// names of the kinds, the sigmoid feature and the velocity effects' torques against their
// formulas, and items that parse back to the same spec.
#include "inertial/model/joint_effect.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <stdexcept>
#include <string>

namespace inertial {
namespace {

TEST(EffectList, ParsesKindsTargetsAndOptions) {
  const std::vector<EffectSpec> e =
      ParseEffectList("viscous, coulomb@j1:scale=0.05,payload@tool:mass=2:radius=0.1,rotor@j0:gear=-6.5");
  ASSERT_EQ(e.size(), 4u);
  EXPECT_EQ(e[0].kind, EffectKind::kViscous);
  EXPECT_TRUE(e[0].target.empty());
  EXPECT_EQ(e[1].kind, EffectKind::kCoulomb);
  EXPECT_EQ(e[1].target, "j1");
  EXPECT_DOUBLE_EQ(e[1].velocity_scale, 0.05);
  EXPECT_DOUBLE_EQ(e[2].mass, 2.0);
  EXPECT_DOUBLE_EQ(e[2].radius, 0.1);
  EXPECT_DOUBLE_EQ(e[3].gear_ratio, -6.5);
  EXPECT_TRUE(ParseEffectList("").empty());
}

TEST(EffectList, RejectsMalformedItemsNamingThem) {
  auto message = [](const std::string& text) {
    try {
      ParseEffectList(text);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message("friction").find("unknown kind 'friction'"), std::string::npos);
  EXPECT_NE(message("payload").find("needs a target"), std::string::npos);
  EXPECT_NE(message("rotor@knee").find("gear ratio"), std::string::npos);
  EXPECT_NE(message("coulomb:scale=abc").find("'abc' is not a number"), std::string::npos);
  EXPECT_NE(message("coulomb:scale=-1").find("must be positive"), std::string::npos);
  EXPECT_NE(message("viscous:scale=1").find("unknown option 'scale'"), std::string::npos);
  EXPECT_NE(message("viscous,,offset").find("empty item"), std::string::npos);
  EXPECT_NE(message("viscous@").find("empty target"), std::string::npos);
  EXPECT_NE(message("sigmoid:steepness=0").find("must be positive"), std::string::npos);
  EXPECT_NE(message("sigmoid:shift=x").find("'x' is not a number"), std::string::npos);
  EXPECT_NE(message("asymmetric:shift=0.1").find("unknown option 'shift'"), std::string::npos);
}

TEST(EffectList, KindNamesAndValueCounts) {
  std::set<std::string> names;
  for (EffectKind k : AllEffectKinds()) names.insert(std::string(ToString(k)));
  EXPECT_EQ(names, (std::set<std::string>{"viscous", "coulomb", "offset", "armature", "spring", "payload", "rotor",
                                          "asymmetric", "sigmoid", "gain"}));
  EXPECT_TRUE(IsJointEffect(EffectKind::kSigmoid));
  EXPECT_TRUE(IsJointEffect(EffectKind::kGain));
  EXPECT_TRUE(IsMeasurementEffect(EffectKind::kGain));
  EXPECT_FALSE(IsMeasurementEffect(EffectKind::kViscous));
  EXPECT_EQ(EffectValueNames(EffectKind::kGain), std::vector<std::string>{"g"});
  EXPECT_FALSE(IsJointEffect(EffectKind::kPayload));
  EXPECT_FALSE(IsJointEffect(EffectKind::kRotor));
  EXPECT_EQ(NumEffectValues(EffectKind::kSpring), 2);
  EXPECT_EQ(NumEffectValues(EffectKind::kAsymmetric), 2);
  EXPECT_EQ(NumEffectValues(EffectKind::kCoulomb), 1);
  EXPECT_EQ(NumEffectValues(EffectKind::kPayload), 0);
  for (EffectKind kind : AllEffectKinds()) {
    EXPECT_EQ(static_cast<int>(EffectValueNames(kind).size()), NumEffectValues(kind)) << ToString(kind);
  }
}

// The torques from the catalog's formulas, S(x) = 1 / (1 + e^-x).
TEST(EffectList, VelocityEffectTorquesAreTheirFormulas) {
  auto S = [](double x) { return 1.0 / (1.0 + std::exp(-x)); };
  for (double qd : {-0.3, -0.004, 0.0, 0.002, 0.5}) {
    EXPECT_NEAR(SigmoidFriction(qd, 40.0, 0.02), S(40.0 * (qd + 0.02)) - S(40.0 * 0.02), 1e-15) << qd;
    EffectSpec spec;
    spec.kind = EffectKind::kViscous;
    EXPECT_NEAR(VelocityEffectTorque(spec, {0.7}, qd), 0.7 * qd, 1e-15);
    spec.kind = EffectKind::kCoulomb;
    spec.velocity_scale = 0.01;
    EXPECT_NEAR(VelocityEffectTorque(spec, {1.2}, qd), 1.2 * std::tanh(qd / 0.01), 1e-15);
    spec.kind = EffectKind::kAsymmetric;
    const double s = std::tanh(qd / 0.01);
    EXPECT_NEAR(VelocityEffectTorque(spec, {1.5, 0.5}, qd), 1.5 * std::max(s, 0.0) + 0.5 * std::min(s, 0.0), 1e-15);
    spec.kind = EffectKind::kSigmoid;
    spec.steepness = 40.0;
    spec.shift = 0.02;
    EXPECT_NEAR(VelocityEffectTorque(spec, {2.0}, qd), 2.0 * (S(40.0 * (qd + 0.02)) - S(0.8)), 1e-14);
    spec.kind = EffectKind::kOffset;
    EXPECT_EQ(VelocityEffectTorque(spec, {-0.25}, qd), -0.25);
    spec.kind = EffectKind::kArmature;  // not a velocity effect
    EXPECT_TRUE(std::isnan(VelocityEffectTorque(spec, {1.0}, qd)));
  }
  EXPECT_EQ(SigmoidFriction(0.0, 50.0, 0.03), 0.0);  // zero at rest
}

TEST(EffectList, ItemsParseBackToTheSameSpec) {
  for (const char* item : {"viscous@knee", "coulomb@knee:scale=0.0125", "asymmetric@hip:scale=0.05",
                           "sigmoid@elbow:steepness=40:shift=-0.02", "spring@hip", "rotor@hip:gear=6",
                           "payload@tool0:mass=2:radius=0.1"}) {
    const std::vector<EffectSpec> once = ParseEffectList(item);
    ASSERT_EQ(once.size(), 1u) << item;
    const std::string text = EffectItem(once[0]);
    const std::vector<EffectSpec> twice = ParseEffectList(text);
    ASSERT_EQ(twice.size(), 1u) << text;
    EXPECT_EQ(twice[0].kind, once[0].kind) << text;
    EXPECT_EQ(twice[0].target, once[0].target) << text;
    EXPECT_DOUBLE_EQ(twice[0].velocity_scale, once[0].velocity_scale) << text;
    EXPECT_DOUBLE_EQ(twice[0].steepness, once[0].steepness) << text;
    EXPECT_DOUBLE_EQ(twice[0].shift, once[0].shift) << text;
    EXPECT_DOUBLE_EQ(twice[0].gear_ratio, once[0].gear_ratio) << text;
    EXPECT_DOUBLE_EQ(twice[0].mass, once[0].mass) << text;
    EXPECT_DOUBLE_EQ(twice[0].radius, once[0].radius) << text;
  }
  EXPECT_EQ(EffectItem(ParseEffectList("coulomb@knee:scale=0.0125")[0]), "coulomb@knee:scale=0.0125");
}

}  // namespace
}  // namespace inertial
