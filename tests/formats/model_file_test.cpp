// Model files (model_file.hpp, the URDF effects of urdf_model.hpp): a model written and read back
// predicts the same torques (every effect kind, rotors, payloads, merged links), bad files are
// refused naming the element, and the standard <dynamics> of other tools' URDFs is read.
#include "inertial/formats/model_file.hpp"

#include <gtest/gtest.h>

#include <filesystem>

#include "inertial/formats/urdf_writer.hpp"
#include "formats/urdf_text.hpp"
#include "simulated_robot.hpp"
#include "test_support.hpp"

namespace inertial {
namespace {

using testing::ErrorOf;
using testing::Example;
using testing::ReadTextFile;
using testing::TempUrdfPath;
using testing::WriteTextFile;

// Every kind: viscous and Coulomb (non-default scale) everywhere, offset, armature, a spring, a
// rotor behind a gearbox, a payload on a link merged by a fixed joint (foot).
const char* kAllEffects =
    "viscous,coulomb:scale=0.05,offset@abad,armature@knee,spring@hip,rotor@hip:gear=6,payload@foot:mass=0.8,"
    "asymmetric@abad:scale=0.03,sigmoid@knee:steepness=35:shift=-0.02";

// The model a file holds: its effects with their values, x from them.
struct ReadBack {
  RobotModel robot;
  std::optional<RobotDynamics> model;
  Eigen::VectorXd x;
};

ReadBack Read(const std::string& path) {
  ReadBack r;
  r.robot = LoadUrdf(path);
  std::vector<EffectSpec> specs;
  for (const ModelEffect& m : r.robot.effects) specs.push_back(m.spec);
  r.model.emplace(MakeRobotDynamics(r.robot, specs));
  r.x = r.model->ParametersFromEffectValues(r.robot.effects);
  return r;
}

// Largest |tau_a - tau_b| over random states, relative to the largest |tau_a|.
double PredictionDifference(const RobotDynamics& a, const Eigen::VectorXd& xa, const RobotDynamics& b,
                            const Eigen::VectorXd& xb, unsigned seed) {
  testing::Rng rng(seed);
  double worst = 0.0, scale = 0.0;
  for (int s = 0; s < 50; ++s) {
    Eigen::VectorXd q(a.num_dofs()), qd(a.num_dofs()), qdd(a.num_dofs());
    for (int j = 0; j < a.num_dofs(); ++j) {
      q[j] = rng.Uniform(-2, 2);
      qd[j] = rng.Uniform(-3, 3);
      qdd[j] = rng.Uniform(-10, 10);
    }
    const Eigen::VectorXd ta = a.InverseDynamics(xa, q, qd, qdd), tb = b.InverseDynamics(xb, q, qd, qdd);
    worst = std::max(worst, (ta - tb).cwiseAbs().maxCoeff());
    scale = std::max(scale, ta.cwiseAbs().maxCoeff());
  }
  return worst / scale;
}

TEST(ModelFile, EveryEffectKindRoundTripsToTheSamePredictions) {
  const RobotModel robot = LoadUrdf(Example("leg3.urdf"));
  const RobotDynamics model = MakeRobotDynamics(robot, ParseEffectList(kAllEffects));
  // One value per effect feature: viscous x3, coulomb x3, offset, armature, spring (k, k q0),
  // asymmetric (bp, bn), sigmoid.
  const Eigen::VectorXd x =
      testing::TrueParameters(model, {0.3, 0.2, 0.25, 0.4, 0.3, 0.2, -0.15, 0.02, 1.5, 0.1, 0.4, 0.25, 0.6}, 7);
  ASSERT_EQ(model.num_features() - model.num_inertia_features(), 13);
  const auto path = TempUrdfPath("all_effects.urdf");
  WriteModelUrdf(Example("leg3.urdf"), path.string(), robot, model, SnapshotAt(model, x), "a test");
  const ReadBack back = Read(path.string());
  // Every effect term and body came back: same counts, and the same predictions to rounding
  // (%.17g numbers; the log-Cholesky maps start from priors equal to the written bodies).
  EXPECT_EQ(back.model->effects().size(), model.effects().size());
  EXPECT_EQ(back.model->bodies().size(), model.bodies().size());
  EXPECT_EQ(back.robot.DeclaredEffects().size(), back.robot.effects.size());
  EXPECT_LT(PredictionDifference(model, x, *back.model, back.x, 3), 1e-12);
  // The Coulomb scales and the sigmoid's shape are kept.
  for (const EffectTerm& t : back.model->effects()) {
    if (t.kind == EffectKind::kCoulomb) {
      EXPECT_EQ(t.velocity_scale, 0.05);
    }
    if (t.kind == EffectKind::kAsymmetric) {
      EXPECT_EQ(t.velocity_scale, 0.03);
    }
    if (t.kind == EffectKind::kSigmoid) {
      EXPECT_EQ(t.steepness, 35.0);
      EXPECT_EQ(t.shift, -0.02);
    }
  }
  // Writing what was read gives the same file content for the model (a fixed point).
  const auto again = TempUrdfPath("all_effects_again.urdf");
  WriteModelUrdf(path.string(), again.string(), back.robot, *back.model, SnapshotAt(*back.model, back.x), "a test");
  const ReadBack third = Read(again.string());
  EXPECT_LT(PredictionDifference(model, x, *third.model, third.x, 4), 1e-12);
  std::filesystem::remove(path);
  std::filesystem::remove(again);
}

TEST(ModelFile, MergedLinksCarryTheirBodyOnce) {
  // leg3's foot is fixed to the shank: the written shank holds both, the foot's <inertial> goes.
  const RobotModel robot = LoadUrdf(Example("leg3.urdf"));
  const RobotDynamics model = MakeRobotDynamics(robot, {});
  const Eigen::VectorXd x = testing::TrueParameters(model, {0.0}, 11);
  const auto path = TempUrdfPath("merged.urdf");
  WriteModelUrdf(Example("leg3.urdf"), path.string(), robot, model, SnapshotAt(model, x), "a test");
  const ReadBack back = Read(path.string());
  EXPECT_LT(PredictionDifference(model, x, *back.model, back.x, 5), 1e-12);
  for (const UrdfLinkInertial& l : back.robot.links) {
    if (l.link == "foot") {
      EXPECT_FALSE(l.present);
    }
  }
  std::filesystem::remove(path);
}

TEST(ModelFile, EffectsTheModelDropsAreZeroedInDynamics) {
  // A file whose <dynamics> state friction the model does not have: written with zeros, so that a
  // reader does not add it back.
  const std::string xml = testing::RobotXml(
      "r", testing::LinkXml("base") +
               testing::JointXml("j", "continuous", "base", "l", Vector3::Zero(), Vector3::Zero(), Vector3::UnitZ(),
                                 "<dynamics damping=\"0.7\" friction=\"0.3\"/>") +
               testing::LinkXml("l", testing::InertialXml(1.0, Vector3(0.1, 0, 0), Vector3::Zero(),
                                                          Matrix3::Identity() * 0.01)));
  const auto in = TempUrdfPath("dyn_in.urdf"), out = TempUrdfPath("dyn_out.urdf");
  WriteTextFile(in, xml);
  const RobotModel robot = LoadUrdf(in.string());
  // Other tools' <dynamics>: read as effects (for validate), but not declared (not fitted).
  ASSERT_EQ(robot.effects.size(), 2u);
  EXPECT_EQ(robot.effects[0].spec.kind, EffectKind::kViscous);
  EXPECT_EQ(robot.effects[0].values[0], 0.7);
  EXPECT_EQ(robot.effects[1].spec.kind, EffectKind::kCoulomb);
  EXPECT_EQ(robot.effects[1].values[0], 0.3);
  EXPECT_EQ(robot.effects[1].spec.velocity_scale, 0.01);
  EXPECT_TRUE(robot.DeclaredEffects().empty());
  const RobotDynamics model = MakeRobotDynamics(robot, ParseEffectList("offset"));
  Eigen::VectorXd x = Eigen::VectorXd::Zero(model.num_parameters());
  x[x.size() - 1] = 0.25;
  WriteModelUrdf(in.string(), out.string(), robot, model, SnapshotAt(model, x), "a test");
  const RobotModel back = LoadUrdf(out.string());
  ASSERT_EQ(back.effects.size(), 1u);
  EXPECT_EQ(back.effects[0].spec.kind, EffectKind::kOffset);
  EXPECT_EQ(back.effects[0].values[0], 0.25);
  EXPECT_NE(ReadTextFile(out).find("damping=\"0\""), std::string::npos);
  std::filesystem::remove(in);
  std::filesystem::remove(out);
}

TEST(ModelFile, BadEffectElementsAreRefusedNamingThem) {
  auto with = [](const std::string& dynamics, const std::string& effects) {
    return testing::RobotXml(
        "r", testing::LinkXml("base") +
                 testing::JointXml("j", "continuous", "base", "l", Vector3::Zero(), Vector3::Zero(), Vector3::UnitZ(),
                                   dynamics) +
                 testing::LinkXml("l", testing::InertialXml(1.0, Vector3(0.1, 0, 0), Vector3::Zero(),
                                                            Matrix3::Identity() * 0.01)) +
                 "<inertial_effects version=\"1\">" + effects + "</inertial_effects>\n");
  };
  const std::string ok_dyn = "<dynamics damping=\"0.1\" friction=\"0.2\"/>";
  struct Case {
    std::string dynamics, effects, expected;
  };
  const Case cases[] = {
      {ok_dyn, "<coulomb joint=\"j\"/>", "velocity_scale"},
      {ok_dyn, "<armature joint=\"j\" inertia=\"-1\"/>", "must be >= 0"},
      {ok_dyn, "<offset joint=\"j\" torque=\"%s%n\"/>", "is not a number"},
      {ok_dyn, "<offset joint=\"j\" torque=\"nan\"/>", "torque"},
      {ok_dyn, "<offset joint=\"nope\" torque=\"1\"/>", "'nope' is not a moving joint"},
      {ok_dyn, "<offset joint=\"j\" torque=\"1\"/><offset joint=\"j\" torque=\"2\"/>", "stated twice"},
      {ok_dyn, "<friction joint=\"j\"/>", "is not an effect"},
      {"", "<viscous joint=\"j\"/>", "no <dynamics>"},
      {"<dynamics damping=\"-0.1\"/>", "", "must be >= 0"},
      {"<dynamics damping=\"1e999\"/>", "", "damping"},
      {ok_dyn, "<spring joint=\"j\" stiffness=\"2\"/>", "rest_position"},
      {ok_dyn, "<asymmetric joint=\"j\" velocity_scale=\"0.01\" positive=\"1\"/>", "negative"},
      {ok_dyn, "<asymmetric joint=\"j\" velocity_scale=\"0\" positive=\"1\" negative=\"1\"/>", "velocity_scale"},
      {ok_dyn, "<asymmetric joint=\"j\" velocity_scale=\"1\" positive=\"-1\" negative=\"1\"/>", "must be >= 0"},
      {ok_dyn, "<sigmoid joint=\"j\" amplitude=\"1\" steepness=\"-3\" shift=\"0\"/>", "steepness"},
      {ok_dyn, "<sigmoid joint=\"j\" amplitude=\"1\" steepness=\"30\"/>", "shift"},
      {ok_dyn, "<rotor joint=\"j\" gear_ratio=\"6\"/>", "no <inertial>"},
      {ok_dyn, "<rotor joint=\"j\" gear_ratio=\"0\"><inertial><mass value=\"1\"/></inertial></rotor>", "gear_ratio"},
      {ok_dyn,
       "<payload link=\"l\"><inertial><mass value=\"1\"/><inertia ixx=\"1\" iyy=\"1\" izz=\"5\" ixy=\"0\" "
       "iyz=\"0\" ixz=\"0\"/></inertial></payload>",
       "not physically consistent"},
  };
  for (const Case& c : cases) {
    const std::string message = ErrorOf([&] { ParseUrdf(with(c.dynamics, c.effects), "bad.urdf"); });
    EXPECT_NE(message.find("bad.urdf"), std::string::npos) << message;
    EXPECT_NE(message.find(c.expected), std::string::npos) << c.effects << " -> " << message;
  }
}

// <inertial_priors> (urdf_model.hpp): read into recorded_priors, or refused naming what is wrong.
TEST(ModelFile, RecordedPriorsAreReadStrictly) {
  const std::string inertial =
      testing::InertialXml(1.0, Vector3(0.1, 0, 0), Vector3::Zero(), Matrix3::Identity() * 0.01);
  auto with = [&](const std::string& priors) {
    return testing::RobotXml("r", testing::LinkXml("base") + testing::LinkXml("plate") +
                                      testing::JointXml("bolt", "fixed", "base", "plate") +
                                      testing::JointXml("j", "continuous", "plate", "l") + testing::LinkXml("l", inertial) +
                                      priors + "\n");
  };
  const RobotModel read = ParseUrdf(with("<inertial_priors version=\"1\"><prior link=\"l\">" + inertial +
                                         "</prior></inertial_priors>"),
                                    "ok.urdf");
  ASSERT_EQ(read.recorded_priors.size(), 1u);
  EXPECT_LT((read.recorded_priors.at("l").vector() - read.tree.inertia(0).vector()).norm(), 1e-15);
  EXPECT_TRUE(ParseUrdf(with(""), "none.urdf").recorded_priors.empty());
  const std::pair<std::string, std::string> cases[] = {
      {"<inertial_priors version=\"2\"></inertial_priors>", "has version '2'; this reader knows version 1"},
      {"<inertial_priors version=\"1\"><payload link=\"l\"/></inertial_priors>", "is not a <prior>"},
      {"<inertial_priors version=\"1\"><prior link=\"plate\">" + inertial + "</prior></inertial_priors>",
       "'plate' is not a link that moves with a joint"},
      {"<inertial_priors version=\"1\"><prior link=\"l\"/></inertial_priors>", "must hold exactly one <inertial>"},
      {"<inertial_priors version=\"1\"><prior link=\"l\" mass=\"1\">" + inertial + "</prior></inertial_priors>",
       "unknown attribute 'mass'"},
      {"<inertial_priors version=\"1\"><prior link=\"l\">" + inertial + "</prior><prior link=\"l\">" + inertial +
           "</prior></inertial_priors>",
       "link 'l' is given twice"},
      {"<inertial_priors version=\"1\"><prior link=\"l\"><inertial><mass value=\"1\"/><inertia ixx=\"1\" "
       "iyy=\"1\" izz=\"5\" ixy=\"0\" iyz=\"0\" ixz=\"0\"/></inertial></prior></inertial_priors>",
       "not physically consistent"},
  };
  for (const auto& [priors_text, expected] : cases) {
    const std::string priors = priors_text;  // a structured binding cannot be captured in C++17 (clang refuses)
    const std::string message = ErrorOf([&] { ParseUrdf(with(priors), "bad.urdf"); });
    EXPECT_NE(message.find("bad.urdf: <inertial_priors>"), std::string::npos) << message;
    EXPECT_NE(message.find(expected), std::string::npos) << priors << " -> " << message;
  }
}

TEST(ModelFile, DeclaredEffectsJoinTheFittingModelAndCommandLineOnesReplaceThem) {
  const std::vector<EffectSpec> file = ParseEffectList("viscous@hip,coulomb@knee:scale=0.02,payload@foot");
  const std::vector<EffectSpec> merged = MergeEffects(file, ParseEffectList("coulomb:scale=0.1"));
  ASSERT_EQ(merged.size(), 3u);
  EXPECT_EQ(merged[0].text, "viscous@hip");
  EXPECT_EQ(merged[1].text, "payload@foot");
  EXPECT_EQ(merged[2].velocity_scale, 0.1);
}

}  // namespace
}  // namespace inertial
