// inertiald's command-line settings over its options: given values replace, empty ones keep, and
// every bad value is refused naming its option.
#include "inertial/config/daemon_overrides.hpp"

#include <gtest/gtest.h>

#include <string>

namespace inertial {
namespace {

std::string ErrorOf(const DaemonOverrides& overrides) {
  DaemonOptions options;
  try {
    ApplyDaemonOverrides(overrides, &options);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(DaemonOverrides, EmptyValuesKeepTheOptionsAndFreshIsAlwaysApplied) {
  DaemonOptions options;
  options.input_channel = "FROM_CONFIG";
  options.publish_rate_hz = 20.0;
  options.checkpoint_path = "config.ckpt";
  options.start_fresh = true;
  ApplyDaemonOverrides(DaemonOverrides{}, &options);
  EXPECT_EQ(options.input_channel, "FROM_CONFIG");
  EXPECT_EQ(options.publish_rate_hz, 20.0);
  EXPECT_EQ(options.checkpoint_path, "config.ckpt");
  EXPECT_EQ(options.estimator.kind, EstimatorKind::kGaussNewton);
  EXPECT_FALSE(options.start_fresh);
}

TEST(DaemonOverrides, GivenValuesReplaceTheOptions) {
  DaemonOverrides o;
  o.lcm_url = "memq://";
  o.channel = "ARM";
  o.estimate_channel = "ARM_ESTIMATE";
  o.residual_channel = "ARM_RESIDUAL";
  o.checkpoint = "arm.ckpt";
  o.estimator = "linear_rls";
  o.log_level = "debug";
  o.publish_rate = "2.5";
  o.checkpoint_interval = "30";
  o.noise_tau = "0.05";
  o.fresh = true;
  DaemonOptions options;
  ApplyDaemonOverrides(o, &options);
  EXPECT_EQ(options.lcm_url, "memq://");
  EXPECT_EQ(options.input_channel, "ARM");
  EXPECT_EQ(options.estimate_channel, "ARM_ESTIMATE");
  EXPECT_EQ(options.residual_channel, "ARM_RESIDUAL");
  EXPECT_EQ(options.checkpoint_path, "arm.ckpt");
  EXPECT_EQ(options.estimator.kind, EstimatorKind::kLinearRls);
  EXPECT_EQ(options.log_level, LogLevel::kDebug);
  EXPECT_EQ(options.publish_rate_hz, 2.5);
  EXPECT_EQ(options.checkpoint_interval_s, 30.0);
  EXPECT_EQ(options.estimator.measurement_sigma, 0.05);
  EXPECT_TRUE(options.start_fresh);
}

TEST(DaemonOverrides, BadValuesAreRefusedNamingTheirOption) {
  DaemonOverrides o;
  o.publish_rate = "0";
  EXPECT_EQ(ErrorOf(o), "--publish-rate must be positive");
  o = {};
  o.checkpoint_interval = "-3";
  EXPECT_EQ(ErrorOf(o), "--checkpoint-interval must be positive");
  o = {};
  o.noise_tau = "abc";
  EXPECT_EQ(ErrorOf(o), "--noise-tau: 'abc' is not a number");
  o = {};
  o.estimator = "kalman";
  EXPECT_EQ(ErrorOf(o), "unknown estimator 'kalman' (gauss_newton, ekf, gradient, linear_rls)");
  o = {};
  o.log_level = "loud";
  EXPECT_EQ(ErrorOf(o), "log level 'loud' is not one of error, warn, info, debug");
}

}  // namespace
}  // namespace inertial
