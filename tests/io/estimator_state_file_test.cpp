// Estimator state files: a saved and loaded state restores an estimator that continues bit for
// bit like the original; malformed files are refused naming the file and the problem.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "inertial/estimation/online_body_estimator.hpp"
#include "inertial/inertia/closed_form_bodies.hpp"
#include "inertial/io/estimator_state_file.hpp"
#include "inertial/model/rigid_body_regressor.hpp"
#include "io/urdf_text.hpp"

namespace inertial {
namespace {

BodySample Sample(int k) {
  BodySample s;
  s.t = 0.01 * k;
  for (int i = 0; i < 6; ++i) {
    s.twist[i] = std::sin(0.7 * s.t * (i + 1) + i);
    s.acceleration[i] = 0.7 * (i + 1) * std::cos(0.7 * s.t * (i + 1) + i);
  }
  s.has_acceleration = true;
  s.gravity = Vector3(0, 0, -9.81);
  s.wrench = RigidBodyRegressor(s.twist, s.acceleration, s.gravity) * SolidBox(1.2, 0.2, 0.1, 0.3).vector();
  s.wrench[k % 6] += 0.01 * std::sin(k);
  return s;
}

TEST(EstimatorStateFile, SavedAndLoadedContinuesBitForBit) {
  OnlineEstimatorOptions o;
  o.measurement_sigma = 0.01;
  OnlineBodyEstimator a(SolidSphere(1.0, 0.05), o), b(SolidSphere(1.0, 0.05), o);
  for (int k = 0; k < 300; ++k) a.Update(Sample(k));
  const std::string path = testing::TempUrdfPath("state.json").string();
  SaveEstimatorState(path, a.estimator().State(), "one body");
  std::string model;
  const EstimatorState loaded = LoadEstimatorState(path, &model);
  EXPECT_EQ(model, "one body");
  EXPECT_EQ(loaded.x, a.estimator().parameters());
  EXPECT_EQ(loaded.P, a.estimator().Covariance());
  std::string why;
  ASSERT_TRUE(b.estimator().Restore(loaded, &why)) << why;
  for (int k = 300; k < 600; ++k) {
    a.Update(Sample(k));
    b.Update(Sample(k));
  }
  EXPECT_EQ(a.estimator().parameters(), b.estimator().parameters());
  EXPECT_EQ(a.estimator().counters().count, b.estimator().counters().count);
}

TEST(EstimatorStateFile, MalformedFilesAreNamed) {
  const std::string path = testing::TempUrdfPath("bad.json").string();
  auto expect_error = [&](const std::string& text, const std::string& what) {
    testing::WriteTextFile(path, text);
    try {
      LoadEstimatorState(path);
      ADD_FAILURE() << "accepted: " << text;
    } catch (const StateFileError& e) {
      EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
  };
  expect_error("{not json", "not an estimator state");
  expect_error("{\"format\": \"something else\"}", "not an estimator state");
  expect_error("{\"format\": \"inertial-estimator-state\", \"version\": 7}", "version 7");
  expect_error("{\"format\": \"inertial-estimator-state\", \"version\": 1, \"kind\": \"gauss_newton\", \"x\": [1, 2], "
               "\"P\": [[1, 0]], \"has_time\": false, \"last_time\": 0, \"counters\": {}}",
               "covariance has 1 rows");
  expect_error("{\"format\": \"inertial-estimator-state\", \"version\": 1, \"kind\": \"gauss_newton\", \"x\": \"x\"}",
               "malformed");
  EXPECT_THROW(LoadEstimatorState("/nonexistent/state.json"), StateFileError);
  EXPECT_THROW(SaveEstimatorState("/nonexistent/dir/state.json", EstimatorState(), ""), StateFileError);
}

}  // namespace
}  // namespace inertial
