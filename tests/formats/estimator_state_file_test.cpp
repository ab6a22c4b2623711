// Estimator state files: a saved and loaded state restores an estimator that continues bit for
// bit like the original; malformed files are refused naming the file and the problem.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <vector>

#include "inertial/estimation/online/online_body_estimator.hpp"
#include "inertial/inertia/closed_form_bodies.hpp"
#include "inertial/formats/estimator_state_file.hpp"
#include "inertial/formats/input_file.hpp"
#include "inertial/model/rigid_body_regressor.hpp"
#include "formats/urdf_text.hpp"

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
  // A number that overflows a double, a negative or fractional counter: the documented error.
  const std::string head = "{\"format\": \"inertial-estimator-state\", \"version\": 1, \"kind\": \"gauss_newton\", ";
  expect_error(head + "\"x\": [1e400], \"P\": [], \"has_time\": false, \"last_time\": 0, \"counters\": {}}",
               "not an estimator state");
  expect_error(head + "\"x\": [1], \"P\": [], \"has_time\": false, \"last_time\": 0, \"counters\": {\"accepted\": -3}}",
               "counter \"accepted\" is -3, not an integer from 0 to 18446744073709551615");
  expect_error(head + "\"x\": [1], \"P\": [], \"has_time\": false, \"last_time\": 0, \"counters\": {\"accepted\": 2.5}}",
               "counter \"accepted\" is 2.5, not an integer");
  expect_error(head + "\"x\": [1], \"P\": [], \"has_time\": false, \"last_time\": 0, \"counters\": {\"accepted\": 1e300}}",
               "counter \"accepted\" is 1e+300, not an integer");
  EXPECT_THROW(LoadEstimatorState("/nonexistent/state.json"), StateFileError);
  EXPECT_THROW(SaveEstimatorState("/nonexistent/dir/state.json", EstimatorState(), ""), StateFileError);
}

// Issue 35: a version read by get<int>() was undefined behaviour for 1e308 ("version -2147483648")
// and truncated 1.9 to 1, accepting the file. Versions are integers checked before any conversion.
TEST(EstimatorStateFile, AVersionThatIsNotAnIntegerInRangeIsRefusedAsWritten) {
  const std::string path = testing::TempUrdfPath("version.json").string();
  auto error_of = [&](const std::string& text) -> std::string {
    testing::WriteTextFile(path, text);
    try {
      LoadEstimatorState(path);
    } catch (const StateFileError& e) {
      return e.what();
    }
    ADD_FAILURE() << "accepted: " << text;
    return "";
  };
  EXPECT_EQ(error_of(R"({"format": "inertial-estimator-state", "version": 1e308})"),
            path + ": \"version\" is 1e+308, not an integer from 1 to 1000000");
  // 200,000 nested arrays as the version: named by kind (writing them out overflowed the stack).
  EXPECT_EQ(error_of(R"({"format": "inertial-estimator-state", "version": )" + std::string(200000, '[') +
                     std::string(200000, ']') + "}"),
            path + ": \"version\" is an array, not an integer from 1 to 1000000");
  // A whole checkpoint, good but for its version.
  OnlineBodyEstimator a(SolidSphere(1.0, 0.05));
  for (int k = 0; k < 20; ++k) a.Update(Sample(k));
  std::string good = EstimatorStateToJson(a.estimator().State(), "one body");
  const std::string version = "\"version\":1";
  ASSERT_NE(good.find(version), std::string::npos) << good.substr(0, 200);
  for (const auto& [written, expected] : std::vector<std::pair<std::string, std::string>>{
           {"1.9", "is 1.9, not an integer"}, {"-1", "is -1, not an integer"}, {"\"1\"", "is \"1\", not an integer"},
           {"true", "is true, not an integer"}, {"2", "estimator state version 2, this program reads version 1"}}) {
    std::string text = good;
    text.replace(text.find(version), version.size(), "\"version\":" + written);
    const std::string message = error_of(text);
    EXPECT_NE(message.find(expected), std::string::npos) << written << ": " << message;
  }
  // 1.0 is the integer 1 (JSON does not tell them apart): the state loads.
  std::string one = good;
  one.replace(one.find(version), version.size(), "\"version\":1.0");
  testing::WriteTextFile(path, one);
  EXPECT_EQ(LoadEstimatorState(path).x, a.estimator().parameters());
  std::filesystem::remove(path);
}

TEST(EstimatorStateFile, AFileOverTheSizeLimitIsRefusedBeforeParsing) {
  const std::string path = testing::TempUrdfPath("huge.json").string();
  {
    std::ofstream out(path, std::ios::binary);
    out.seekp(static_cast<std::streamoff>(kMaxStateFileBytes));  // a sparse file one byte over the limit
    out.put(' ');
  }
  try {
    LoadEstimatorState(path);
    ADD_FAILURE() << "accepted";
  } catch (const StateFileError& e) {
    EXPECT_EQ(std::string(e.what()), path + ": the estimator state is 33554433 bytes, over its limit of 32 MiB: refused before parsing");
  }
  std::filesystem::remove(path);
}


// States that would wedge the estimator (every later sample refused, the bad state written back at
// every checkpoint) are refused by Restore with the reason, and the estimator is left as it was.
TEST(EstimatorStateFile, UnusableStatesAreRefusedAndChangeNothing) {
  OnlineEstimatorOptions o;
  o.measurement_sigma = 0.01;
  OnlineBodyEstimator a(SolidSphere(1.0, 0.05), o), b(SolidSphere(1.0, 0.05), o);
  for (int k = 0; k < 100; ++k) a.Update(Sample(k));
  const EstimatorState good = a.estimator().State();
  const Eigen::VectorXd x_before = b.estimator().parameters();
  struct Case {
    std::string name;
    EstimatorState state;
    std::string expected;
  };
  std::vector<Case> cases;
  EstimatorState s = good;
  s.P = -good.P;
  cases.push_back({"negative definite P", s, "not positive definite"});
  s = good;
  s.P(0, 1) += 1.0;
  cases.push_back({"asymmetric P", s, "not symmetric"});
  s = good;
  s.P.setZero();
  cases.push_back({"zero P", s, "not positive definite"});
  s = good;
  s.x[0] = 1e300;
  cases.push_back({"x = 1e300", s, "beyond"});
  s = good;
  s.x[0] = 30.0;  // log-Cholesky: mass e^60 times the prior's
  cases.push_back({"x = 30", s, "beyond"});
  s = good;
  s.last_time = 1e300;
  cases.push_back({"last_time = 1e300", s, "out of order"});
  for (const Case& c : cases) {
    std::string why;
    EXPECT_FALSE(b.estimator().Restore(c.state, &why)) << c.name;
    EXPECT_NE(why.find(c.expected), std::string::npos) << c.name << ": " << why;
    EXPECT_EQ(b.estimator().parameters(), x_before) << c.name << " changed the estimate";
  }
  std::string why;
  EXPECT_TRUE(b.estimator().Restore(good, &why)) << why;
}

}  // namespace
}  // namespace inertial
