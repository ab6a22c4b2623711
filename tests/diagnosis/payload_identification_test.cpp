// Payload identification (payload_identification.hpp) on simulated runs of the bundled 7-DOF arm
// holding a 1-3 kg box of random pose on its flange (tool0): the mass within 2 % and the COM within
// 5 mm of the truth, against the model (links as the URDF states them, viscous friction fitted) and
// from the difference with a baseline run of the same trajectory (links 10 % off the URDF and
// friction the model does not know, both cancelling); a baseline of another trajectory, or of the
// same one 5 ms late, is refused.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>

#include "../../examples/bundled_robots.hpp"
#include "inertial/diagnosis/payload_identification.hpp"
#include "inertial/estimation/fit_uncertainty.hpp"
#include "inertial/inertia/closed_form_bodies.hpp"
#include "inertial/model/fourier_trajectory.hpp"
#include "inertial/model/joint_simulation.hpp"
#include "test_support.hpp"

namespace inertial {
namespace {

constexpr double kSigmaTau = 0.1;  // torque noise [N m], as the arm's other simulated tests
constexpr double kSeconds = 12;
constexpr double kRateHz = 200;

// A box of 1-3 kg, 8 x 6 x 10 cm, randomly turned, its COM up to 5 cm off the flange axis and 2-12
// cm beyond the flange, in tool0's frame.
InertialParams RandomPayload(unsigned seed) {
  testing::Rng rng(seed);
  const double mass = rng.Uniform(1.0, 3.0);
  const Vector3 com(rng.Uniform(-0.05, 0.05), rng.Uniform(-0.05, 0.05), rng.Uniform(0.02, 0.12));
  return SolidBox(mass, 0.08, 0.06, 0.10, Pose{rng.Rotation(), com});
}

// x of `model` with its payload@tool0 set to `payload` (given in tool0's frame).
void SetPayload(const RobotDynamics& model, const InertialParams& payload, Eigen::VectorXd* x) {
  const int e = PayloadBody(model, "tool0");
  const EstimatedBody& body = model.bodies()[e];
  const Vector10 pi_tree = ReportFrameMap(body).inverse() * payload.vector();
  x->segment<10>(10 * e) = body.map.ThetaOf(InertialParams::FromVector(pi_tree));
}

// The arm tracking Fourier excitation `trajectory_seed` (5 harmonics, 0.1 Hz, 0.9 rad), as
// testing::SimulateLogs does, torques with noise of seed `noise_seed`.
JointSamples SimulateRun(const RobotDynamics& model, const Eigen::VectorXd& x, std::uint64_t trajectory_seed,
                 std::uint64_t noise_seed) {
  const Eigen::VectorXd w = model.Coefficients(x);
  const JointDynamicsFn plant = [&](const Eigen::VectorXd& q, const Eigen::VectorXd& qd, const Eigen::VectorXd& qdd) {
    return model.InverseDynamicsFromCoefficients(w, q, qd, qdd);
  };
  const FourierTrajectory reference = RandomFourierTrajectory(model.num_dofs(), 5, 0.1, 0.9, trajectory_seed);
  JointSimulationOptions options;
  options.duration = kSeconds;
  options.sample_rate_hz = kRateHz;
  options.internal_step = 5e-4;
  const double bandwidth = 2 * M_PI * 5.0;
  options.kp = Eigen::VectorXd::Constant(1, bandwidth * bandwidth);
  options.kd = Eigen::VectorXd::Constant(1, 2 * 0.7 * bandwidth);
  const JointSamples clean = SimulateTracking(plant, plant, [&](double t) { return reference.Evaluate(t); }, options,
                                              model.dof_names());
  return AddGaussianNoise(clean, SampleNoise{0, 0, 0, kSigmaTau}, noise_seed);
}

void ExpectPayload(const PayloadIdentification& r, const InertialParams& truth) {
  EXPECT_NEAR(r.payload.mass(), truth.mass(), 0.02 * truth.mass()) << "std " << r.uncertainty.mass;
  EXPECT_LT((r.payload.com() - truth.com()).norm(), 0.005)
      << "COM " << r.payload.com().transpose() << " truth " << truth.com().transpose();
  EXPECT_FALSE(r.held.mass);
  for (bool held : r.held.com) EXPECT_FALSE(held);
  // The residual is the noise: nothing left unexplained.
  EXPECT_LT(r.residual_rms, 1.5 * kSigmaTau * (r.from_difference ? std::sqrt(2.0) : 1.0));
}

TEST(PayloadIdentification, AgainstTheModelLinksAsTheUrdfStatesThem) {
  const examples::BundledRobot arm = examples::Arm7();
  const RobotDynamics model = arm.Dynamics("viscous,payload@tool0");
  for (unsigned seed : {1u, 2u}) {
    const InertialParams truth = RandomPayload(seed);
    Eigen::VectorXd x = model.ParametersFromEffectCoefficients(Eigen::VectorXd::Constant(7, 0.5));
    SetPayload(model, truth, &x);
    const JointSamples with = SimulateRun(model, x, 10 + seed, 20 + seed);
    const PayloadIdentification r = IdentifyPayload(model, "tool0", with);
    SCOPED_TRACE("seed " + std::to_string(seed) + ", mass " + std::to_string(truth.mass()));
    EXPECT_FALSE(r.from_difference);
    EXPECT_EQ(r.num_samples, with.size());
    ExpectPayload(r, truth);
    // The links stayed at the URDF; the friction was fitted.
    EXPECT_TRUE(r.fit.x.head(70).isZero(0));
    EXPECT_NEAR(model.EffectValues(0, r.fit.x)[0], 0.5, 0.05);
  }
}

TEST(PayloadIdentification, FromTheDifferenceWithABaselineRun) {
  const examples::BundledRobot arm = examples::Arm7();
  // The truth: links 10 % off the URDF (theta in [-0.1, 0.1]) and friction, in both runs; the
  // fitted model knows neither.
  const RobotDynamics with_model = arm.Dynamics("viscous,coulomb,payload@tool0");
  const RobotDynamics without_model = arm.Dynamics("viscous,coulomb");
  const RobotDynamics fit_model = arm.Dynamics("payload@tool0");
  for (unsigned seed : {3u, 4u}) {
    const InertialParams truth = RandomPayload(seed);
    testing::Rng rng(100 + seed);
    Eigen::VectorXd x_without = without_model.ParametersFromEffectCoefficients(Eigen::VectorXd::Constant(14, 0.4));
    for (int i = 0; i < 70; ++i) x_without[i] = rng.Uniform(-0.1, 0.1);
    Eigen::VectorXd x_with(with_model.num_parameters());
    x_with << x_without.head(70), Eigen::VectorXd::Zero(10), x_without.tail(14);
    SetPayload(with_model, truth, &x_with);
    const JointSamples with = SimulateRun(with_model, x_with, 30 + seed, 40 + seed);
    const JointSamples baseline = SimulateRun(without_model, x_without, 30 + seed, 50 + seed);
    const PayloadIdentification r = IdentifyPayloadFromDifference(fit_model, "tool0", with, baseline);
    SCOPED_TRACE("seed " + std::to_string(seed) + ", mass " + std::to_string(truth.mass()));
    EXPECT_TRUE(r.from_difference);
    EXPECT_LT(r.position_mismatch, 0.001);
    ExpectPayload(r, truth);
  }
}

TEST(PayloadIdentification, RefusesABaselineOfAnotherTrajectory) {
  const examples::BundledRobot arm = examples::Arm7();
  const RobotDynamics model = arm.Dynamics("payload@tool0");
  const Eigen::VectorXd x = Eigen::VectorXd::Zero(model.num_parameters());
  const JointSamples with = SimulateRun(model, x, 5, 6);
  const JointSamples other = SimulateRun(model, x, 7, 8);
  try {
    PayloadDifferenceSamples(model, "tool0", with, other, 0.01);
    ADD_FAILURE() << "a baseline of another trajectory was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("do not follow the same trajectory: joint"), std::string::npos)
        << e.what();
  }
  // The same trajectory 5 ms late (one sample at 200 Hz): about 0.2 % of joint2's range, which
  // moved a 1.1 kg payload's COM by 6 mm (the header's measurement); refused at the default 0.1 %.
  JointSamples late = with;
  const int n = with.size() - 1;
  late.t = with.t.tail(n).eval();
  late.q = with.q.bottomRows(n).eval();
  late.qd = with.qd.bottomRows(n).eval();
  late.qdd = with.qdd.bottomRows(n).eval();
  late.tau = with.tau.bottomRows(n).eval();
  EXPECT_THROW(PayloadDifferenceSamples(model, "tool0", with, late, PayloadIdentificationOptions().max_position_mismatch),
               std::invalid_argument);
  double mismatch = 0;
  PayloadDifferenceSamples(model, "tool0", with, late, 1.0, &mismatch);
  EXPECT_GT(mismatch, 0.001);
  EXPECT_LT(mismatch, 0.004);
  // Joint effects do not belong in the difference's model, and the payload must be in it.
  EXPECT_THROW(PayloadDifferenceSamples(arm.Dynamics("viscous,payload@tool0"), "tool0", with, with, 0.01),
               std::invalid_argument);
  EXPECT_THROW(PayloadDifferenceSamples(model, "link3", with, with, 0.01), std::invalid_argument);
}

}  // namespace
}  // namespace inertial
