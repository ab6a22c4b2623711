// The parameter layout of the online estimators: its Jacobian against central differences (a
// layout built by hand with every block kind, and the layout of a robot with every effect kind),
// the mass / COM / inertia-about-COM map against the parallel-axis theorem and central differences,
// and the first-order uncertainty of the COM against a Monte Carlo.
#include "inertial/estimation/parameter_layout.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "estimation/body_stream.hpp"
#include "inertial/inertia/closed_form_bodies.hpp"
#include "inertial/model/robot_dynamics.hpp"
#include "leg_chain.hpp"
#include "test_support.hpp"

namespace inertial {
namespace {

using testing::Rng;
using testing::TrueBody;

TEST(ParameterLayout, JacobianMatchesCentralDifferences) {
  Rng rng(31);
  const InertialParams p1 = SolidBox(2.0, 0.3, 0.2, 0.1), p2 = SolidSphere(0.5, 0.05);
  // Two bodies on one feature block (a link and its payload), an offset, an exp coefficient, a spring.
  const ParameterLayout layout(25, {BodyBlock{LogCholeskyParameterization(p1), 0, 0}, BodyBlock{LogCholeskyParameterization(p2), 0, 10}},
                               {ScalarBlock{ScalarMap::kLinear, 20, 20}, ScalarBlock{ScalarMap::kExponential, 21, 21},
                                ScalarBlock{ScalarMap::kSpring, 22, 22}});
  ASSERT_EQ(layout.num_parameters(), 24);
  for (int trial = 0; trial < 20; ++trial) {
    Eigen::MatrixXd A(4, 25);
    for (int i = 0; i < A.size(); ++i) A.data()[i] = rng.Normal();
    Eigen::VectorXd x(24);
    for (int i = 0; i < 24; ++i) x[i] = rng.Uniform(-1, 1);
    Eigen::VectorXd w(25);
    Eigen::MatrixXd H(4, 24);
    layout.Evaluate(x, A, w, H);
    Eigen::VectorXd w2(25);
    layout.Coefficients(x, w2);
    EXPECT_LT((w - w2).norm(), 1e-14);
    EXPECT_LT((w.head<10>() - layout.Body(0, x).vector() - layout.Body(1, x).vector()).norm(), 1e-12);
    Eigen::MatrixXd H_fd(4, 24);
    const double h = 1e-6;
    for (int j = 0; j < 24; ++j) {
      Eigen::VectorXd xp = x, xm = x, wp(25), wm(25);
      xp[j] += h;
      xm[j] -= h;
      layout.Coefficients(xp, wp);
      layout.Coefficients(xm, wm);
      H_fd.col(j) = A * (wp - wm) / (2 * h);
    }
    EXPECT_LT((H - H_fd).norm() / H_fd.norm(), 1e-7);
  }
  EXPECT_THROW(ParameterLayout(10, {BodyBlock{LogCholeskyParameterization(p1), 5, 0}}, {}), std::invalid_argument);
  EXPECT_THROW(ParameterLayout(12, {BodyBlock{LogCholeskyParameterization(p1), 0, 0}}, {ScalarBlock{ScalarMap::kLinear, 10, 9}}),
               std::invalid_argument);
}

// The online estimators' layout of a robot holds every effect kind as RobotDynamics does (the
// asymmetric friction's two levels both e^s, the sigmoid's level e^s): same w(x), and H = A J_w
// against central differences.
TEST(ParameterLayout, FromRobotMatchesTheModelForEveryEffectKind) {
  Rng rng(32);
  const RobotDynamics model(testing::LegChain(testing::LegPriorLinks()), testing::kLegJoints,
                            ParseEffectList("viscous,coulomb,offset@abad,armature@knee,spring@hip,asymmetric@hip,"
                                            "sigmoid@knee:steepness=30:shift=0.01"),
                            testing::NoLinks());
  const ParameterLayout layout = ParameterLayout::FromRobot(model);
  ASSERT_EQ(layout.num_parameters(), model.num_parameters());
  const int P = model.num_parameters(), F = model.num_features();
  for (int trial = 0; trial < 10; ++trial) {
    Eigen::VectorXd x(P);
    for (int i = 0; i < P; ++i) x[i] = rng.Uniform(-0.5, 0.5);
    Eigen::VectorXd w(F);
    layout.Coefficients(x, w);
    EXPECT_LT((w - model.Coefficients(x)).norm(), 1e-13 * (1 + w.norm()));
    Eigen::MatrixXd A(3, F);
    for (int i = 0; i < A.size(); ++i) A.data()[i] = rng.Normal();
    Eigen::MatrixXd H(3, P);
    layout.Evaluate(x, A, w, H);
    Eigen::MatrixXd H_fd(3, P);
    const double h = 1e-6;
    for (int j = 0; j < P; ++j) {
      Eigen::VectorXd xp = x, xm = x;
      xp[j] += h;
      xm[j] -= h;
      H_fd.col(j) = A * (model.Coefficients(xp) - model.Coefficients(xm)) / (2 * h);
    }
    EXPECT_LT((H - H_fd).norm() / H_fd.norm(), 1e-7);
  }
}

// The COM's standard deviation through its Jacobian, against a Monte Carlo of c = h / m over
// Gaussian pi with the same covariance (an independent, derivative-free reference).
TEST(BodyUncertainty, ComStandardDeviationMatchesMonteCarlo) {
  const InertialParams body = TrueBody();
  Matrix10 L = Matrix10::Zero();
  Rng rng(41);
  for (int i = 0; i < 10; ++i) {
    for (int j = 0; j <= i; ++j) L(i, j) = rng.Normal(i == j ? 1e-3 : 3e-4);
  }
  const Matrix10 C = L * L.transpose();
  const BodyUncertainty u = UncertaintyOf(body, C);
  EXPECT_DOUBLE_EQ(u.mass, std::sqrt(C(0, 0)));
  Vector3 sum = Vector3::Zero(), sum_sq = Vector3::Zero();
  const int N = 200000;
  for (int k = 0; k < N; ++k) {
    Vector10 z;
    for (int i = 0; i < 10; ++i) z[i] = rng.Normal();
    const Vector10 pi = body.vector() + L * z;
    const Vector3 c = pi.segment<3>(1) / pi[0];
    sum += c;
    sum_sq += c.cwiseProduct(c);
  }
  const Vector3 mean = sum / N;
  const Vector3 sd = (sum_sq / N - mean.cwiseProduct(mean)).cwiseSqrt();
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(u.com[i], sd[i], 0.02 * sd[i]) << i;
}

// A box whose centre is offset and rotated: mass and COM are those it was built with, and the
// inertia about the COM is the box's own principal inertia rotated into the frame (closed form),
// whatever the offset; the analytic Jacobian matches central differences.
TEST(ParameterLayout, MassComInertiaAboutComIsTheParallelAxisTheorem) {
  Rng rng(33);
  for (int trial = 0; trial < 10; ++trial) {
    const double m = rng.Uniform(0.5, 3.0), a = rng.Uniform(0.05, 0.4), b = rng.Uniform(0.05, 0.4), c = rng.Uniform(0.05, 0.4);
    const Pose pose = rng.RandomPose<Pose>(0.3);
    const InertialParams body = SolidBox(m, a, b, c, pose);
    Matrix10 J;
    const Vector10 mci = MassComInertiaAboutCom(body, &J);
    EXPECT_NEAR(mci[mci_index::kMass], m, 1e-14);
    EXPECT_LT((mci.segment<3>(mci_index::kCx) - pose.p_BoCo_B).norm(), 1e-13);
    const Vector3 principal(m * (b * b + c * c) / 12, m * (a * a + c * c) / 12, m * (a * a + b * b) / 12);
    const Matrix3 I_C = pose.R_BC * principal.asDiagonal() * pose.R_BC.transpose();
    const int k = mci_index::kIxx;
    const Vector6 expected(I_C(0, 0), I_C(1, 1), I_C(2, 2), I_C(0, 1), I_C(1, 2), I_C(0, 2));
    EXPECT_LT((mci.segment<6>(k) - expected).cwiseAbs().maxCoeff(), 1e-13) << trial;
    const Matrix10 J_fd = testing::CentralDifference<10, 10>(
        [](const Vector10& pi) { return MassComInertiaAboutCom(InertialParams::FromVector(pi)); }, body.vector());
    EXPECT_LT(testing::RelativeError(J, J_fd), 1e-7) << trial;
  }
}

}  // namespace
}  // namespace inertial
