// Standard deviations from an estimator's covariance (covariance_uncertainty.hpp) against an
// independent first-order propagation: on the leg with an offset, a viscous term, an asymmetric
// form and a spring, every reported std equals sqrt(g^T P g) with g the central-difference
// gradient, in the estimate, of the quantity itself (mass, COM, inertia about the COM from
// RobotDynamics::BodyInertia; the effect values from RobotDynamics::EffectValues), for a random
// covariance; the same for linear RLS's coefficients (the bodies' pi straight from w, the effect
// values through ParametersFromEffectCoefficients); and sizes that do not match are refused.
#include "inertial/estimation/covariance_uncertainty.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <stdexcept>

#include "estimation/leg_chain.hpp"
#include "test_support.hpp"

namespace inertial {
namespace {

using testing::Rng;

RobotDynamics Leg() {
  return RobotDynamics(testing::LegChain(testing::LegPriorLinks()), testing::kLegJoints,
                       ParseEffectList("offset@abad,viscous@hip,asymmetric@knee,spring@hip"), testing::NoLinks());
}

// mass, COM, inertia about the COM [Ixx Iyy Izz Ixy Iyz Ixz].
Eigen::VectorXd Quantities(const InertialParams& b) {
  Eigen::VectorXd v(10);
  const Vector3 c = b.com();
  const Matrix3 I = b.rotational_inertia_about_com();
  v << b.mass(), c.x(), c.y(), c.z(), I(0, 0), I(1, 1), I(2, 2), I(0, 1), I(1, 2), I(0, 2);
  return v;
}

// sqrt(g^T P g) per output of f, g by central differences of f at x (step h relative to |x_i| + 1).
Eigen::VectorXd PropagatedStd(const std::function<Eigen::VectorXd(const Eigen::VectorXd&)>& f, const Eigen::VectorXd& x,
                              const Eigen::MatrixXd& P, double h = 1e-6) {
  const Eigen::VectorXd f0 = f(x);
  Eigen::MatrixXd G(f0.size(), x.size());
  for (int i = 0; i < x.size(); ++i) {
    const double step = h * (std::abs(x[i]) + 1.0);
    Eigen::VectorXd xp = x, xm = x;
    xp[i] += step;
    xm[i] -= step;
    G.col(i) = (f(xp) - f(xm)) / (2.0 * step);
  }
  return (G * P * G.transpose()).diagonal().cwiseSqrt();
}

Eigen::MatrixXd RandomCovariance(int n, double scale, Rng* rng) {
  Eigen::MatrixXd A(n, n);
  for (int i = 0; i < n; ++i) {
    for (int k = 0; k < n; ++k) A(i, k) = rng->Normal(scale);
  }
  return A * A.transpose() / n;
}

void ExpectStds(const BodyUncertainty& u, const Eigen::VectorXd& reference, const std::string& what) {
  Eigen::VectorXd got(10);
  got << u.mass, u.com, u.inertia_about_com;
  for (int i = 0; i < 10; ++i) {
    EXPECT_NEAR(got[i], reference[i], 1e-5 * reference[i] + 1e-12) << what << " quantity " << i;
  }
}

TEST(CovarianceUncertainty, ParametersMatchCentralDifferencePropagation) {
  const RobotDynamics model = Leg();
  Rng rng(7);
  Eigen::VectorXd x(model.num_parameters());
  for (int i = 0; i < x.size(); ++i) x[i] = rng.Uniform(-0.3, 0.3);
  const Eigen::MatrixXd P = RandomCovariance(static_cast<int>(x.size()), 0.05, &rng);
  const CovarianceUncertainty u = UncertaintyFromCovariance(model, x, P, false);
  ASSERT_EQ(u.bodies.size(), model.bodies().size());
  ASSERT_EQ(u.body_stds.size(), model.bodies().size());
  for (int e = 0; e < static_cast<int>(model.bodies().size()); ++e) {
    EXPECT_TRUE(u.bodies[e].vector().isApprox(model.BodyInertia(e, x).vector(), 1e-14)) << e;
    const Eigen::VectorXd ref =
        PropagatedStd([&](const Eigen::VectorXd& y) { return Quantities(model.BodyInertia(e, y)); }, x, P);
    ExpectStds(u.body_stds[e], ref, model.bodies()[e].name);
    // The pi covariance: the same propagation of pi itself.
    const Eigen::VectorXd pi_std =
        PropagatedStd([&](const Eigen::VectorXd& y) -> Eigen::VectorXd { return model.BodyInertia(e, y).vector(); }, x, P);
    for (int i = 0; i < 10; ++i) EXPECT_NEAR(std::sqrt(u.body_pi_covariance[e](i, i)), pi_std[i], 1e-5 * pi_std[i] + 1e-12);
  }
  ASSERT_EQ(u.effects.size(), model.effects().size());
  for (int k = 0; k < static_cast<int>(model.effects().size()); ++k) {
    const Eigen::VectorXd ref = PropagatedStd(
        [&](const Eigen::VectorXd& y) {
          const std::vector<double> v = model.EffectValues(k, y);
          return Eigen::VectorXd(Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size())));
        },
        x, P);
    ASSERT_EQ(u.effects[k].size(), static_cast<size_t>(ref.size())) << k;
    for (int i = 0; i < ref.size(); ++i) EXPECT_NEAR(u.effects[k][i], ref[i], 1e-5 * ref[i] + 1e-12) << k << " " << i;
  }
}

TEST(CovarianceUncertainty, CoefficientsMatchCentralDifferencePropagation) {
  const RobotDynamics model = Leg();
  Rng rng(8);
  Eigen::VectorXd x(model.num_parameters());
  for (int i = 0; i < x.size(); ++i) x[i] = rng.Uniform(-0.3, 0.3);
  const Eigen::VectorXd w = model.Coefficients(x);
  const Eigen::MatrixXd P = RandomCovariance(static_cast<int>(w.size()), 0.01, &rng);
  const CovarianceUncertainty u = UncertaintyFromCovariance(model, w, P, true);
  for (int e = 0; e < static_cast<int>(model.bodies().size()); ++e) {
    const int b = model.bodies()[e].tree_body;
    const Eigen::VectorXd ref = PropagatedStd(
        [&](const Eigen::VectorXd& y) { return Quantities(InertialParams::FromVector(y.segment<10>(10 * b))); }, w, P);
    ExpectStds(u.body_stds[e], ref, model.bodies()[e].name);
  }
  const int ni = model.num_inertia_features();
  for (int k = 0; k < static_cast<int>(model.effects().size()); ++k) {
    const Eigen::VectorXd ref = PropagatedStd(
        [&](const Eigen::VectorXd& y) {
          const std::vector<double> v =
              model.EffectValues(k, model.ParametersFromEffectCoefficients(y.tail(y.size() - ni)));
          return Eigen::VectorXd(Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size())));
        },
        w, P);
    ASSERT_EQ(u.effects[k].size(), static_cast<size_t>(ref.size())) << k;
    for (int i = 0; i < ref.size(); ++i) EXPECT_NEAR(u.effects[k][i], ref[i], 1e-5 * ref[i] + 1e-12) << k << " " << i;
  }
}

TEST(CovarianceUncertainty, SingleParameterClosedForm) {
  // A viscous term b = e^s with std(s) = 0.2 at b = 2: std(b) = 0.4 (db = b ds).
  const RobotDynamics model(testing::LegChain(testing::LegPriorLinks()), testing::kLegJoints,
                            ParseEffectList("viscous@knee"), testing::NoLinks());
  Eigen::VectorXd x = Eigen::VectorXd::Zero(model.num_parameters());
  x[model.effects()[0].first_parameter] = std::log(2.0);
  const Eigen::MatrixXd P = 0.04 * Eigen::MatrixXd::Identity(x.size(), x.size());
  EXPECT_NEAR(UncertaintyFromCovariance(model, x, P, false).effects[0][0], 0.4, 1e-12);
}

TEST(CovarianceUncertainty, RefusesSizesThatDoNotMatch) {
  const RobotDynamics model = Leg();
  const Eigen::VectorXd x = Eigen::VectorXd::Zero(model.num_parameters());
  EXPECT_THROW(UncertaintyFromCovariance(model, x, Eigen::MatrixXd::Identity(3, 3), false), std::invalid_argument);
  // An estimate of neither the model's parameters nor its coefficients (one value too many).
  const Eigen::VectorXd longer = Eigen::VectorXd::Zero(std::max(model.num_parameters(), model.num_features()) + 1);
  const Eigen::MatrixXd square = Eigen::MatrixXd::Identity(longer.size(), longer.size());
  EXPECT_THROW(UncertaintyFromCovariance(model, longer, square, false), std::invalid_argument);
  EXPECT_THROW(UncertaintyFromCovariance(model, longer, square, true), std::invalid_argument);
}

}  // namespace
}  // namespace inertial
