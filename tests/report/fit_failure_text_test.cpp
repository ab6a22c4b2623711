// The text of a fit that failed numerically, for runs and logs made here: a log with one torque of
// 1e300 (named with its sample, time and column) and a log where nothing stands out.
#include "inertial/report/fit_failure_text.hpp"

#include <gtest/gtest.h>

#include <limits>

namespace inertial {
namespace {

JointSamples Log(double glitch) {
  JointSamples s;
  s.joint_names = {"knee"};
  const int n = 50;
  s.t = Eigen::VectorXd::LinSpaced(n, 0.0, 0.49);
  s.q = s.qd = s.qdd = Eigen::MatrixXd(n, 1);
  s.tau = Eigen::MatrixXd(n, 1);
  for (int i = 0; i < n; ++i) {
    s.q(i, 0) = std::sin(0.3 * i);
    s.qd(i, 0) = std::cos(0.3 * i);
    s.qdd(i, 0) = -std::sin(0.3 * i);
    s.tau(i, 0) = 2 + std::sin(0.7 * i);
  }
  s.tau(20, 0) = glitch;
  return s;
}

IdentificationRun Failed(double data_cost) {
  IdentificationRun run;
  run.fit.lm.reason = StopReason::kNumericalFailure;
  run.fit.data_cost = data_cost;
  return run;
}

TEST(FitFailureText, NamesTheExtremeValueAndTheHint) {
  const std::string text = FitFailureText("run.csv", Failed(std::numeric_limits<double>::infinity()), Log(1e300), true);
  const std::string head =
      "Error: run.csv: the fit failed numerically (stopped on numerical_failure, non-finite cost): the data hold "
      "values no sensor reading can have:\n  sample 20 (t = 0.2 s): tau_knee = 1e+300";
  EXPECT_EQ(text.substr(0, head.size()), head) << text;
  const std::string hint = "\nhint: fix or remove these rows (--skip-bad-rows skips malformed ones)\n";
  ASSERT_GE(text.size(), hint.size());
  EXPECT_EQ(text.substr(text.size() - hint.size()), hint) << text;
  const std::string off = FitFailureText("run.csv", Failed(1.0), Log(1e300), false);
  EXPECT_EQ(off.find("non-finite"), std::string::npos) << off;
  const std::string off_hint = "\nhint: without --no-outlier-rejection such rows are left out\n";
  EXPECT_EQ(off.substr(off.size() - off_hint.size()), off_hint) << off;
}

TEST(FitFailureText, NothingStandsOut) {
  EXPECT_EQ(FitFailureText("run.csv", Failed(2.0), Log(2.5), true),
            "Error: run.csv: the fit failed numerically (stopped on numerical_failure); no value of the data stands "
            "out: check units (--time-scale) and the model\n");
}

}  // namespace
}  // namespace inertial
