// A model against measurements (validation_report.hpp), with errors known by construction: the
// leg's torques computed by its recursive Newton-Euler inverse dynamics plus a constant offset per
// joint, so each joint's RMS error is that offset and its relative RMS the offset over the RMS of
// the torques (summed here); a glitched sample left out and named; and a single body at rest without gravity whose force-bias model predicts the
// bias alone, against a sensor that reads a constant wrench.
#include "inertial/report/validation_report.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>

#include "estimation/leg_chain.hpp"
#include "inertial/inertia/closed_form_bodies.hpp"
#include "simulated_robot.hpp"
#include "test_support.hpp"

namespace inertial {
namespace {

TEST(ValidationReport, JointModelErrorsAreTheOffsetsAdded) {
  const RobotDynamics model(testing::LegChain(testing::LegPriorLinks()), testing::kLegJoints, {}, testing::NoLinks());
  const Eigen::VectorXd x = Eigen::VectorXd::Zero(model.num_parameters());
  const Eigen::VectorXd x_true = testing::TrueParameters(model, {0.0}, 5, 0.25);
  JointSamples data = testing::SimulateLogs(model, x_true, 0.0, 4.0, 5, 100).train;
  const Eigen::Vector3d offset(0.1, -0.2, 0.3);
  Eigen::Vector3d sum_sq = Eigen::Vector3d::Zero();
  for (int i = 0; i < data.size(); ++i) {
    data.tau.row(i) = (model.InverseDynamics(x, data.q.row(i).transpose(), data.qd.row(i).transpose(),
                                             data.qdd.row(i).transpose()) + offset).transpose();
    if (i != 7) sum_sq += data.tau.row(i).transpose().cwiseAbs2();
  }
  const int N = data.size();
  const Eigen::Vector3d tau_rms = (sum_sq / (N - 1)).cwiseSqrt();  // of the samples kept
  data.qd(7, 1) = std::numeric_limits<double>::infinity();  // a glitch: left out and named
  ModelValidation v = ValidateJointModel(model, x, data);
  v.model_source = "leg";
  v.data_source = "log.csv";
  EXPECT_EQ(v.left_out, 1);
  ASSERT_EQ(v.left_out_reasons.size(), 1u);
  EXPECT_EQ(v.left_out_reasons[0].rfind("sample 7 (t = ", 0), 0u) << v.left_out_reasons[0];
  EXPECT_NE(v.left_out_reasons[0].find("qd_hip is not finite or too large to square"), std::string::npos);
  EXPECT_EQ(v.predicted.rows(), N - 1);
  EXPECT_EQ(v.channels, testing::kLegJoints);
  EXPECT_TRUE(v.physically_consistent);
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(v.errors.rms[k], std::abs(offset[k]), 1e-9) << k;
    EXPECT_NEAR(v.errors.relative_rms[k], std::abs(offset[k]) / tau_rms[k], 1e-9) << k;
  }
  EXPECT_NEAR(v.errors.total_rms, std::sqrt(offset.squaredNorm() / 3), 1e-9);

  const nlohmann::json j = ValidationJson(v);
  EXPECT_EQ(j["model"], "leg");
  EXPECT_EQ(j["samples"], N - 1);
  EXPECT_NEAR(j["rms"]["knee"].get<double>(), 0.3, 1e-9);
  EXPECT_NEAR(j["rms"]["total"].get<double>(), std::sqrt(0.14 / 3), 1e-9);
  EXPECT_EQ(j["left_out"]["samples"], 1);
  EXPECT_EQ(j["physically_consistent"], true);
  EXPECT_EQ(j["bodies"].size(), 3u);
  const std::string text = ValidationText(v);
  EXPECT_NE(text.find("Validation of leg on log.csv (" + std::to_string(N - 1) + " samples; no fit"), std::string::npos)
      << text;
  EXPECT_NE(text.find("  hip: 0.2 ("), std::string::npos) << text;
  EXPECT_NE(text.find("  left out: 1 samples"), std::string::npos) << text;
  EXPECT_NE(text.find("Every body of the model is physically consistent."), std::string::npos);

  // Every sample glitched: nothing to validate.
  data.qd.col(0).setConstant(1e300);
  EXPECT_THROW(ValidateJointModel(model, x, data), std::invalid_argument);
  EXPECT_THROW(ValidateJointModel(model, Eigen::VectorXd::Zero(3), data), std::invalid_argument);
}

// At rest, no gravity: the rigid body predicts no wrench, so the force-bias model predicts its bias
// [0 0 0 | 0 0 0.5]; the sensor reads [1 0 0 | 0 0 2]. Errors: mx 1, fz 1.5, the rest 0.
TEST(ValidationReport, BodyAtRestAgainstAConstantWrench) {
  const BodyEffectModel model(SolidBox(1.5, 0.2, 0.1, 0.1), {BodyEffectKind::kForceBias});
  Eigen::VectorXd x = Eigen::VectorXd::Zero(model.num_parameters());
  x[model.first_parameter(0) + 2] = 0.5;
  BodyLog log;
  for (int i = 0; i < 11; ++i) {
    TwistWrenchSample s;
    s.t = 0.01 * i;
    s.wrench << 1, 0, 0, 0, 0, 2;
    log.samples.push_back(s);
  }
  const ModelValidation v = ValidateBodyModel(model, x, log);
  EXPECT_EQ(v.channels, (std::vector<std::string>{"mx", "my", "mz", "fx", "fy", "fz"}));
  ASSERT_EQ(v.predicted.rows(), 10);
  EXPECT_NEAR(v.signals.t[0], 0.005, 1e-15);  // pairs at their midpoints
  Eigen::Matrix<double, 6, 1> rms;
  rms << 1, 0, 0, 0, 0, 1.5;
  EXPECT_LT((v.errors.rms - rms).norm(), 1e-12);
  EXPECT_NEAR(v.errors.relative_rms[5], 0.75, 1e-12);
  EXPECT_NEAR(v.errors.total_rms, std::sqrt((1 + 2.25) / 6), 1e-12);
  EXPECT_TRUE(v.physically_consistent);
  EXPECT_NEAR(v.model_json["body"]["mass"].get<double>(), 1.5, 1e-12);
  EXPECT_EQ(v.model_json["effects"][0]["effect"], "force_bias");
  EXPECT_EQ(v.model_json["effects"][0]["values"], nlohmann::json({0.0, 0.0, 0.5}));
  EXPECT_NE(ValidationText(v).find("sample pairs; no fit"), std::string::npos);

  log.samples.resize(1);
  EXPECT_THROW(ValidateBodyModel(model, x, log), std::invalid_argument);
}

}  // namespace
}  // namespace inertial
