// The paper's midpoint discretization (eq. 13): one pair is the rigid-body regressor at the mean
// twist and the finite-difference acceleration with the mean wrench; the stacked system is second
// order in the sample interval on simulated data; bad samples are named.
#include "inertial/model/midpoint_regression.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "inertial/inertia/closed_form_bodies.hpp"
#include "inertial/model/rigid_body_regressor.hpp"
#include "inertial/model/rigid_body_simulation.hpp"
#include "model/sample_times.hpp"
#include "test_support.hpp"

namespace inertial {
namespace {

using testing::Rng;
using testing::Times;

// Eq. (13) is second order: on exact (simulated, noise-free) data the residual at the true pi
// falls by about 4x when the sample interval halves.
TEST(MidpointRegression, ResidualIsSecondOrderInTheSampleInterval) {
  const InertialParams body = SolidBox(0.7, 0.3, 0.5, 0.8, Pose{Matrix3::Identity(), Vector3(0.1, -0.2, 0.05)});
  auto wrench = [](double s) {
    Vector6 w;
    for (int k = 0; k < 6; ++k) w[k] = std::sin(s + k * M_PI / 3);
    return w;
  };
  double previous = 0.0;
  for (double dt : {0.05, 0.025, 0.0125}) {
    const std::vector<double> t = Times(dt, 2.0);
    const SimulationResult sim = SimulateRigidBody(body, Vector6::Zero(), wrench, t);
    std::vector<TwistWrenchSample> samples;
    for (std::size_t k = 0; k < t.size(); ++k) samples.push_back({t[k], sim.twists[k], wrench(t[k])});
    const LinearRegression reg = BuildMidpointRegression(samples);
    const double rms = std::sqrt((reg.A * body.vector() - reg.b).squaredNorm() / reg.b.size());
    if (previous > 0.0) {
      EXPECT_GT(previous / rms, 3.5) << "dt " << dt;
      EXPECT_LT(previous / rms, 4.5) << "dt " << dt;
    }
    previous = rms;
  }
}

TEST(MidpointRegression, RejectsBadSamplesNamingThem) {
  std::vector<TwistWrenchSample> samples(3);
  samples[0].t = 0.0;
  samples[1].t = 0.1;
  samples[2].t = 0.1;
  try {
    BuildMidpointRegression(samples);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("sample 2: time 0.1"), std::string::npos) << e.what();
  }
  samples[2].t = 0.2;
  samples[1].wrench[3] = std::nan("");
  try {
    BuildMidpointRegression(samples);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("sample 1: non-finite"), std::string::npos) << e.what();
  }
  EXPECT_THROW(BuildMidpointRegression(std::vector<TwistWrenchSample>(1)), std::invalid_argument);
}

// A pair by hand: xi_bar = (xi0 + xi1) / 2, xi_dot = (xi1 - xi0) / dt, w = (w0 + w1) / 2; the
// stacked system holds the pairs in order.
TEST(MidpointRegression, PairIsTheRegressorAtTheMidpoint) {
  Rng rng(5);
  const Vector3 g(0.0, -3.0, -9.0);
  std::vector<TwistWrenchSample> s(3);
  for (int k = 0; k < 3; ++k) {
    s[k].t = 0.1 + 0.02 * k + 0.005 * k * k;
    s[k].twist = rng.UniformVector<6>(-1, 1);
    s[k].wrench = rng.UniformVector<6>(-5, 5);
  }
  Matrix6x10 Y;
  Vector6 w;
  MidpointRegressorPair(s[0], s[1], g, &Y, &w);
  const double dt = s[1].t - s[0].t;
  const Matrix6x10 expected = RigidBodyRegressor(0.5 * (s[0].twist + s[1].twist), (s[1].twist - s[0].twist) / dt, g);
  EXPECT_LT(testing::RelativeError(Y, expected), 1e-14);
  EXPECT_LT(testing::RelativeError(w, Vector6(0.5 * (s[0].wrench + s[1].wrench))), 1e-15);
  const LinearRegression reg = BuildMidpointRegression(s, g);
  ASSERT_EQ(reg.A.rows(), 12);
  ASSERT_EQ(reg.A.cols(), 10);
  ASSERT_EQ(reg.b.size(), 12);
  EXPECT_EQ(Matrix6x10(reg.A.topRows<6>()), Y);
  EXPECT_EQ(Vector6(reg.b.head<6>()), w);
  MidpointRegressorPair(s[1], s[2], g, &Y, &w);
  EXPECT_EQ(Matrix6x10(reg.A.bottomRows<6>()), Y);
  EXPECT_EQ(Vector6(reg.b.tail<6>()), w);
}

}  // namespace
}  // namespace inertial
