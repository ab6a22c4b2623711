// What `inertial diagnose` prints (diagnosis_report.hpp), against hand-made inputs: the residual
// signatures and worst windows as text and JSON, each candidate's one-line explanation (its fitted
// coefficient and the residual's slope, a payload's mass and principal moments worked by hand), the
// bodies' plausibility (masses of the priors at x = 0, infinities as "inf"), and the path of added
// effects. And one diagnosis of the leg chain whose data hide viscous friction b = 0.5 on the knee:
// the JSON's suggestion is that effect, and the explanation's residual slope on velocity is the
// hidden b.
#include "inertial/report/diagnosis_report.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "estimation/leg_chain.hpp"
#include "inertial/inertia/closed_form_bodies.hpp"
#include "simulated_robot.hpp"
#include "test_support.hpp"

namespace inertial {
namespace {

RobotDynamics Leg(const std::string& effects = "") {
  return RobotDynamics(testing::LegChain(testing::LegPriorLinks()), testing::kLegJoints, ParseEffectList(effects),
                       testing::NoLinks());
}

// A dynamic-size vector (TorqueErrors holds these) of three entries.
Eigen::VectorXd Three(double a, double b, double c) {
  Eigen::VectorXd v(3);
  v << a, b, c;
  return v;
}

// Residual signatures of the three joints: the knee's steps by 0.8 at reversals and has slopes 0.25
// on velocity, 0.03 on acceleration, 1.5 on position, a mean of -0.1.
ResidualAnalysis Residuals() {
  ResidualAnalysis r;
  r.joints.resize(3);
  JointResidualSignature& knee = r.joints[2];
  knee.rms = 0.125;
  knee.coefficients[kResidualMean] = -0.1;
  knee.coefficients[kVelocitySign] = 0.4;
  knee.coefficients[kVelocity] = 0.25;
  knee.alone[kResidualMean] = -0.1;
  knee.alone[kVelocitySign] = 0.4;
  knee.alone[kVelocity] = -0.25;
  knee.alone[kAcceleration] = 0.03;
  knee.alone[kPosition] = 1.5;
  knee.alone[kTorque] = 0.02;
  knee.correlations[kVelocity] = 0.9;
  knee.explained = 0.5;
  r.worst_windows.push_back(ResidualWindow{2.0, 3.0, 0.2, 2});
  r.worst_windows.push_back(ResidualWindow{0.0, 1.0, 0.1, 1});
  return r;
}

TEST(DiagnosisReport, WhereItFailsByHand) {
  const ResidualAnalysis r = Residuals();
  const std::string text = WhereItFailsText(testing::kLegJoints, r, "residual of the fit");
  EXPECT_EQ(text.rfind("Where it fails (residual of the fit)\n  worst 1 s windows: t = 2.0-3.0 s RMS 0.2 (worst knee);"
                       " t = 0.0-1.0 s RMS 0.1 (worst hip);\n", 0), 0u) << text;
  EXPECT_NE(text.find("  knee: RMS 0.125; c0 -0.1, step at reversal 0.8, c2 0.25, c3 0, c4 0 (explains 50.0 %); "
                      "slope on tau 0.02\n"), std::string::npos) << text;
  const nlohmann::json j = WhereItFailsJson(testing::kLegJoints, r);
  ASSERT_EQ(j["worst_windows"].size(), 2u);
  EXPECT_EQ(j["worst_windows"][0]["worst_joint"], "knee");
  EXPECT_EQ(j["worst_windows"][1]["t_end"], 1.0);
  EXPECT_EQ(j["joints"]["knee"]["velocity_sign_step"], 0.8);
  EXPECT_EQ(j["joints"]["knee"]["viscous_slope"], 0.25);
  EXPECT_EQ(j["joints"]["knee"]["torque_slope"], 0.02);
  EXPECT_EQ(j["joints"]["knee"]["correlations"]["velocity"], 0.9);
  EXPECT_EQ(j["joints"]["abad"]["rms"], 0.0);
}

TEST(DiagnosisReport, CandidateExplanationsByHand) {
  const RobotDynamics model = Leg();
  JointDiagnosis d;
  d.held_out.residuals = Residuals();
  JointDiagnosisContext c;
  c.model = &model;
  c.diagnosis = &d;
  auto candidate = [](const std::string& item, std::vector<double> values) {
    CandidateResult r;
    r.spec = ParseEffectList(item).at(0);
    r.joint = r.spec.target;
    r.values = std::move(values);
    return r;
  };
  EXPECT_EQ(CandidateExplanation(c, candidate("viscous@knee", {0.5})),
            "the knee residual grows in proportion to velocity (0.25 N m s/rad): viscous friction b = 0.5 N m s/rad "
            "is missing");
  EXPECT_EQ(CandidateExplanation(c, candidate("coulomb@knee", {0.4})),
            "the knee residual steps by 0.8 N m where the velocity changes sign: Coulomb (dry) friction of 0.4 N m is "
            "missing");
  EXPECT_EQ(CandidateExplanation(c, candidate("offset@knee", {-0.1})),
            "the knee residual has a constant part of 0.1 N m: a torque-sensor offset (zero-torque calibration) of "
            "-0.1 N m is missing");
  EXPECT_EQ(CandidateExplanation(c, candidate("spring@knee", {1.5, 0.2})),
            "the knee residual grows with position (1.5 N m/rad): a spring k = 1.5 N m/rad about q0 = 0.2 rad (cable, "
            "hose, gravity compensator) is missing");
  // A payload: a 0.2 kg box of 0.1 x 0.2 x 0.3 m at (0.1, 0, 0); principal moments about its COM
  // m (b^2 + c^2) / 12 ... = 0.00217, 0.00167, 0.000833, sorted ascending.
  CandidateResult payload;
  payload.spec = ParseEffectList("payload@knee_link").at(0);
  payload.link = "knee_link";
  const InertialParams box = SolidBox(0.2, 0.1, 0.2, 0.3, Pose{Matrix3::Identity(), Vector3(0.1, 0, 0)});
  payload.values.assign(box.vector().data(), box.vector().data() + 10);
  payload.payload_std = BodyUncertainty{};
  payload.payload_std->mass = 0.01;
  EXPECT_EQ(CandidateExplanation(c, payload),
            "knee_link carries more than its URDF says: a payload of 0.2 +- 0.01 kg, principal moments [0.000833, "
            "0.00167, 0.00217] kg m^2 about its centre of mass at [0.1, 0, 0] m (in the frame of knee_link's rigid "
            "body) explains the error (or the URDF inertia of that body is wrong)");
}

TEST(DiagnosisReport, PlausibilityJsonAtThePriors) {
  const RobotDynamics model = Leg();
  JointDiagnosis d;
  d.fit.x = Eigen::VectorXd::Zero(model.num_parameters());
  d.links = {true, true, true};
  d.frozen_bodies = {false, false, true};
  d.prior_tolerance = 0.75;
  d.plausibility.resize(3);
  d.plausibility[1].mass_ratio = 6.0;
  d.plausibility[1].factor = 6.0;  // beyond 1.75
  d.plausibility[2].factor = std::numeric_limits<double>::infinity();
  const nlohmann::json j = PlausibilityJson(model, d);
  ASSERT_EQ(j.size(), 3u);
  const std::vector<InertialParams> priors = testing::LegPriorLinks();
  for (int e = 0; e < 3; ++e) {
    EXPECT_NEAR(j[e]["mass"].get<double>(), priors[e].mass(), 1e-12);
    EXPECT_NEAR(j[e]["mass_prior"].get<double>(), priors[e].mass(), 1e-12);
  }
  EXPECT_EQ(j[1]["name"], "hip_link");
  EXPECT_EQ(j[1]["mass_ratio"], 6.0);
  EXPECT_EQ(j[1]["within_tolerance"], false);
  EXPECT_EQ(j[0]["within_tolerance"], true);
  EXPECT_EQ(j[2]["factor"], "inf");
  const std::string text = PlausibilityText(model, d);
  EXPECT_NE(text.find("tolerance: within a factor 1.75, departures counted beyond 2 standard deviations"),
            std::string::npos) << text;
  EXPECT_NE(text.find("  hip_link: mass x6, "), std::string::npos) << text;
  EXPECT_NE(text.find("factor 6  BENT\n"), std::string::npos) << text;
  EXPECT_NE(text.find("(held at the URDF)"), std::string::npos) << text;
  EXPECT_NE(text.find("  ! hip_link identified at 1.5 kg (URDF 1.5 kg)"), std::string::npos) << text;
}

TEST(DiagnosisReport, PathOfAddedEffects) {
  const RobotDynamics model = Leg();
  JointDiagnosis final_diagnosis;
  EXPECT_EQ(DiagnosisPathText({}, final_diagnosis),
            "Effects added in turn (the top suggestion each time):\n  none: nothing was suggested\n"
            "  stopped: nothing more is suggested\n");
  DiagnosisStep s;
  s.added = "viscous@knee";
  s.item = "viscous@knee";
  s.explained = 0.4;
  s.evidence.by_size = true;
  s.evidence.explained = 0.4;
  s.before.rms = Three(0.1, 0.2, 0.3);
  s.before.total_rms = 0.2;
  s.before.total_relative_rms = 0.123;
  s.after.rms = Three(0.1, 0.2, 0.05);
  s.after.total_rms = 0.15;
  s.after.total_relative_rms = 0.05;
  s.bent_before = {"hip_link"};
  final_diagnosis.stop_reason = "the step cap (1) was reached";
  EXPECT_EQ(DiagnosisPathText({s}, final_diagnosis),
            "Effects added in turn (the top suggestion each time):\n"
            "  1. added viscous@knee (explains 40.0 % of the held-out error)\n"
            "     held-out RMS 0.2 (12.3 %) -> 0.15 (5.0 %) N m\n"
            "     links' implausibility 0 -> 0; bent links: hip_link -> none\n"
            "  stopped: the step cap (1) was reached\n");
  const nlohmann::json j = DiagnosisPathJson(model, {s});
  ASSERT_EQ(j.size(), 1u);
  EXPECT_EQ(j[0]["added"], "viscous@knee");
  EXPECT_EQ(j[0]["rms_validation_before"]["knee"], 0.3);
  EXPECT_EQ(j[0]["rms_validation_after"]["knee"], 0.05);
  EXPECT_EQ(j[0]["rms_validation_after"]["total"], 0.15);
  EXPECT_EQ(j[0]["bent_links_before"], nlohmann::json({"hip_link"}));
}

// The leg with viscous friction b = 0.5 on the knee, diagnosed without it.
TEST(DiagnosisReport, JsonOfALegMissingViscousFriction) {
  const auto make = [](const std::vector<EffectSpec>& effects) {
    return RobotDynamics(testing::LegChain(testing::LegPriorLinks()), testing::kLegJoints, effects, testing::NoLinks());
  };
  const RobotDynamics truth = make(ParseEffectList("viscous@knee"));
  const Eigen::VectorXd x_true = testing::TrueParameters(truth, {0.5}, 7, 0.1);
  const testing::SimulatedLogs logs = testing::SimulateLogs(truth, x_true, 0.02, 12.0, 7, 100);
  JointDiagnosisOptions options;
  options.threads = 2;
  const RobotDynamics model = make({});
  const JointDiagnosis d = DiagnoseJointModel(make, {}, {}, logs.train, logs.test, options);
  const JointDiagnosisContext c = MakeJointDiagnosisContext(model, d, "test.csv", options.min_explained);
  // The fit's held-out residual on the knee is -b qd (predicted - measured): slope -0.5 on velocity.
  EXPECT_NEAR(d.held_out.residuals.joints[2].alone[kVelocity], -0.5, 0.05);
  const nlohmann::json j = JointDiagnosisJson(c);
  EXPECT_EQ(j["validation_source"], "test.csv");
  EXPECT_EQ(j["samples"]["validation"], logs.test.size());
  EXPECT_EQ(j["rms_validation"]["knee"], d.fit_validation.rms[2]);
  ASSERT_GE(j["suggestions"].size(), 1u);
  EXPECT_EQ(j["suggestions"][0]["name"], "viscous@knee");
  EXPECT_EQ(j["suggestions"][0]["suggested"], true);
  EXPECT_NEAR(j["suggestions"][0]["values"][0].get<double>(), 0.5, 0.025);
  const std::string explanation = j["suggestions"][0]["explanation"];
  EXPECT_EQ(explanation.rfind("the knee residual grows in proportion to velocity (0.", 0), 0u) << explanation;
  EXPECT_NE(explanation.find("viscous friction b = 0.5 N m s/rad is missing"), std::string::npos) << explanation;
  EXPECT_EQ(j["candidates"].size(), d.candidates.size());
  EXPECT_EQ(j["physically_consistent"], true);
  const std::string text = JointDiagnosisText(c);
  EXPECT_NE(text.find("viscous@knee"), std::string::npos);
}

}  // namespace
}  // namespace inertial
