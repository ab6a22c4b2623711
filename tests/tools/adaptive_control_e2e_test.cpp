// The embedding example (examples/adaptive_control.cpp) run as a program: with the estimator in
// the loop the tracking error falls to a small fraction of the fixed-prior controller's, and the
// payload mass converges to the truth.
#include <gtest/gtest.h>

#include <sstream>

#include "cli_support.hpp"

namespace inertial {
namespace {

TEST(AdaptiveControlExample, TrackingErrorFallsAsThePayloadIsLearned) {
  const char* cli = std::getenv("INERTIAL_CLI");
  ASSERT_NE(cli, nullptr);
  const std::string program = (testing::fs::path(cli).parent_path() / "examples" / "adaptive_control").string();
  const std::string out_path = testing::UniqueTempPath("adaptive.txt").string();
  const std::string command = program + " 3 > " + out_path;
  ASSERT_EQ(std::system(command.c_str()), 0) << command;
  std::istringstream out(testing::ReadFile(out_path));
  std::string line;
  std::getline(out, line);
  double true_mass = 0;
  ASSERT_EQ(std::sscanf(line.c_str(), "unknown payload: %lf kg", &true_mass), 1) << line;
  std::getline(out, line);  // header
  double t = 0, fixed = 0, adaptive = 0, mass = 0, late_fixed = 0, late_adaptive = 0;
  while (std::getline(out, line)) {
    ASSERT_EQ(std::sscanf(line.c_str(), "%lf %lf %lf %lf", &t, &fixed, &adaptive, &mass), 4) << line;
    if (t > 0.5) {  // once the payload has been learned (the law's first steps, docs/online.md)
      late_fixed += fixed;
      late_adaptive += adaptive;
    }
  }
  EXPECT_NEAR(t, 3.0, 1e-9);
  EXPECT_LT(late_adaptive, 0.02 * late_fixed);  // far below the fixed prior's, all along
  EXPECT_LT(adaptive, 0.01 * fixed);
  EXPECT_NEAR(mass, true_mass, 0.01 * true_mass);
}

}  // namespace
}  // namespace inertial
