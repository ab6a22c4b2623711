// Payload identification (payload_identification.hpp) on simulated runs of the bundled 7-DOF arm
// holding a 1-3 kg box of random pose on its flange (tool0): the mass within 2 % and the COM within
// 5 mm of the truth, against the model (links as the URDF states them, viscous friction fitted) and
// from the difference with a baseline run of the same trajectory (links 10 % off the URDF and
// friction the model does not know, both cancelling); the same from a baseline recorded late or
// early (5-50 ms, the shift found and removed) and from a with-run that tracks the path differently
// (the payload's own tracking error under a controller that does not know it, a scaled path: the
// model transports the baseline's torque); a baseline of another trajectory is refused.
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
  // One draw per statement: the order in which a call's arguments are evaluated is unspecified
  // (GCC takes them right to left on x86-64, left to right on aarch64), and the cases' measured
  // figures need the same payload on both. Drawn z, y, x as the x86-64 build drew them.
  const double z = rng.Uniform(0.02, 0.12);
  const double y = rng.Uniform(-0.05, 0.05);
  const double x = rng.Uniform(-0.05, 0.05);
  const Vector3 com(x, y, z);
  return SolidBox(mass, 0.08, 0.06, 0.10, Pose{rng.Rotation(), com});
}

// x of `model` with its payload@tool0 set to `payload` (given in tool0's frame).
void SetPayload(const RobotDynamics& model, const InertialParams& payload, Eigen::VectorXd* x) {
  const int e = PayloadBody(model, "tool0");
  const EstimatedBody& body = model.bodies()[e];
  const Vector10 pi_tree = ReportFrameMap(body).inverse() * payload.vector();
  x->segment<10>(10 * e) = body.map.ThetaOf(InertialParams::FromVector(pi_tree));
}

// How a run tracks the excitation (default: from its start, exactly, the controller knowing the plant).
struct Tracking {
  double lag = 0;    ///< [s] the log's time t shows the reference at t + lag (recording started lag late)
  double scale = 0;  ///< the reference scaled about its start by 1 + scale
  double bandwidth_hz = 5;  ///< the computed-torque loop's
  /// The controller's model (default: the plant's): a model without the payload leaves the
  /// payload's torque to the feedback, which tracks with an error the payload makes.
  const RobotDynamics* nominal = nullptr;
  const Eigen::VectorXd* nominal_x = nullptr;
};

// The arm tracking Fourier excitation `trajectory_seed` (5 harmonics, 0.1 Hz, 0.9 rad), as
// testing::SimulateLogs does, torques with noise of seed `noise_seed`.
JointSamples SimulateRun(const RobotDynamics& model, const Eigen::VectorXd& x, std::uint64_t trajectory_seed,
                         std::uint64_t noise_seed, const Tracking& tracking = {}) {
  const Eigen::VectorXd w = model.Coefficients(x);
  const JointDynamicsFn plant = [&](const Eigen::VectorXd& q, const Eigen::VectorXd& qd, const Eigen::VectorXd& qdd) {
    return model.InverseDynamicsFromCoefficients(w, q, qd, qdd);
  };
  const RobotDynamics& nominal_model = tracking.nominal != nullptr ? *tracking.nominal : model;
  const Eigen::VectorXd w_nominal = tracking.nominal != nullptr ? nominal_model.Coefficients(*tracking.nominal_x) : w;
  const JointDynamicsFn nominal = [&](const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                                      const Eigen::VectorXd& qdd) {
    return nominal_model.InverseDynamicsFromCoefficients(w_nominal, q, qd, qdd);
  };
  const FourierTrajectory reference = RandomFourierTrajectory(model.num_dofs(), 5, 0.1, 0.9, trajectory_seed);
  const Eigen::VectorXd q_start = reference.Evaluate(0).q;
  JointSimulationOptions options;
  options.duration = kSeconds;
  options.sample_rate_hz = kRateHz;
  options.internal_step = 5e-4;
  const double bandwidth = 2 * M_PI * tracking.bandwidth_hz;
  options.kp = Eigen::VectorXd::Constant(1, bandwidth * bandwidth);
  options.kd = Eigen::VectorXd::Constant(1, 2 * 0.7 * bandwidth);
  const JointReferenceFn tracked = [&](double t) {
    JointTrajectoryPoint p = reference.Evaluate(t + tracking.lag);
    p.q = q_start + (1 + tracking.scale) * (p.q - q_start);
    p.qd *= 1 + tracking.scale;
    p.qdd *= 1 + tracking.scale;
    return p;
  };
  const JointSamples clean = SimulateTracking(plant, nominal, tracked, options, model.dof_names());
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
  // ... and white: no model error is claimed (payload_identification.hpp, "Model error").
  EXPECT_FALSE(r.model_error) << "residual " << r.residual_rms << ", sample-to-sample " << r.residual_white_noise;
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

// The difference tests' robot: the truth has links 10 % off the URDF (theta in [-0.1, 0.1]) and
// viscous and Coulomb friction 0.4, in both runs; the fitted model knows neither.
struct DifferenceCase {
  examples::BundledRobot arm = examples::Arm7();
  RobotDynamics with_model = arm.Dynamics("viscous,coulomb,payload@tool0");
  RobotDynamics without_model = arm.Dynamics("viscous,coulomb");
  RobotDynamics fit_model = arm.Dynamics("payload@tool0");
  InertialParams truth;
  Eigen::VectorXd x_with, x_without;

  explicit DifferenceCase(unsigned seed) : truth(RandomPayload(seed)) {
    testing::Rng rng(100 + seed);
    x_without = without_model.ParametersFromEffectCoefficients(Eigen::VectorXd::Constant(14, 0.4));
    for (int i = 0; i < 70; ++i) x_without[i] = rng.Uniform(-0.1, 0.1);
    x_with.resize(with_model.num_parameters());
    x_with << x_without.head(70), Eigen::VectorXd::Zero(10), x_without.tail(14);
    SetPayload(with_model, truth, &x_with);
  }
};

TEST(PayloadIdentification, FromTheDifferenceWithABaselineRun) {
  for (unsigned seed : {3u, 4u}) {
    const DifferenceCase c(seed);
    const JointSamples with = SimulateRun(c.with_model, c.x_with, 30 + seed, 40 + seed);
    const JointSamples baseline = SimulateRun(c.without_model, c.x_without, 30 + seed, 50 + seed);
    const PayloadIdentification r = IdentifyPayloadFromDifference(c.fit_model, "tool0", with, baseline);
    SCOPED_TRACE("seed " + std::to_string(seed) + ", mass " + std::to_string(c.truth.mass()));
    EXPECT_TRUE(r.from_difference);
    // Both runs start with the motion and track it (all but the integration's last digits): nothing
    // to shift or transport (a shift of a microsecond may leave the last sample out).
    EXPECT_LT(std::abs(r.pairing.time_shift), 1e-5);
    EXPECT_LT(r.pairing.position_mismatch, 1e-4);
    EXPECT_LT(r.pairing.mismatch_torque, 0.001);
    EXPECT_GE(r.pairing.num_pairs, with.size() - 1);
    ExpectPayload(r, c.truth);
    // The same run against the model, whose links are 10 % off and which lacks the friction: the
    // residual is mostly the model's error, smooth in time, and the fit says so.
    const PayloadIdentification against = IdentifyPayload(c.fit_model, "tool0", with);
    EXPECT_TRUE(against.model_error) << "residual " << against.residual_rms << ", sample-to-sample "
                                     << against.residual_white_noise;
  }
}

// A baseline whose recording started late (or early) in the motion: at the same time since start
// its positions are 0.18-2.0 % of joint2's range off, which the pairing by time alone turned into
// up to 6 % of mass and 71 mm of COM (docs/payload.md). The shift is found to 1 us (measured
// within 0.8 us; a sample is 5 ms) and the payload is then as good as with a baseline that started
// with the motion: measured at most 0.025 % of mass and 0.57 mm of COM, both the noise's. The
// bounds, 0.2 % and 2 mm, are below what a shift one sample off costs (5 ms: 0.42 % and 6 mm), so
// that they test the shift, not only the 1 % and 5 mm.
TEST(PayloadIdentification, FromTheDifferenceWithABaselineRecordedLate) {
  for (unsigned seed : {3u, 4u}) {
    const DifferenceCase c(seed);
    const JointSamples with = SimulateRun(c.with_model, c.x_with, 30 + seed, 40 + seed);
    for (double lag : {0.005, 0.020, 0.050, -0.0075}) {
      Tracking late;
      late.lag = lag;
      const JointSamples baseline = SimulateRun(c.without_model, c.x_without, 30 + seed, 50 + seed, late);
      const PayloadIdentification r = IdentifyPayloadFromDifference(c.fit_model, "tool0", with, baseline);
      SCOPED_TRACE("seed " + std::to_string(seed) + ", mass " + std::to_string(c.truth.mass()) + ", late by " +
                   std::to_string(1000 * lag) + " ms");
      EXPECT_NEAR(r.pairing.time_shift, -lag, 1e-5);
      EXPECT_GT(r.pairing.position_mismatch_unshifted, 0.0015);
      EXPECT_LT(r.pairing.position_mismatch, 1e-4);
      EXPECT_LT(r.pairing.mismatch_torque, 0.001);
      EXPECT_NEAR(r.payload.mass(), c.truth.mass(), 0.002 * c.truth.mass());
      EXPECT_LT((r.payload.com() - c.truth.com()).norm(), 0.002)
          << "COM " << r.payload.com().transpose() << " truth " << c.truth.com().transpose();
      ExpectPayload(r, c.truth);
    }
  }
}

// A with-run that tracks the path differently, as a robot under another load does: (a) the
// controller does not know the payload and its 20 Hz loop tracks with the error the payload's
// torque makes (0.3-0.9 % of the range); (b) that, the path scaled by 1.008 about its start, and the
// baseline recorded 20 ms late (0.5-1.0 % of the range after the shift). No shift removes these:
// the model transports the baseline's torque. Measured: at most 0.21 % of mass and 1.9 mm of COM
// (the pairing by time alone: up to 5.2 % and 32 mm, and 3.3 % for the scaled path without the
// lag). Asserted: the 1 % and 5 mm, a margin of 2.6 times on the COM, which depends on how
// the links' errors (random, 10 %) meet the mismatch.
TEST(PayloadIdentification, FromTheDifferenceWithARunThatTracksDifferently) {
  for (unsigned seed : {3u, 4u}) {
    const DifferenceCase c(seed);
    for (bool scaled_and_late : {false, true}) {
      Tracking loaded;  // the with-run: the controller's model has no payload
      loaded.bandwidth_hz = 20;
      loaded.nominal = &c.without_model;
      loaded.nominal_x = &c.x_without;
      Tracking base;
      base.bandwidth_hz = 20;
      if (scaled_and_late) {
        loaded.scale = 0.008;
        base.lag = 0.020;
      }
      const JointSamples with = SimulateRun(c.with_model, c.x_with, 30 + seed, 40 + seed, loaded);
      const JointSamples baseline = SimulateRun(c.without_model, c.x_without, 30 + seed, 50 + seed, base);
      const PayloadIdentification r = IdentifyPayloadFromDifference(c.fit_model, "tool0", with, baseline);
      SCOPED_TRACE("seed " + std::to_string(seed) + ", mass " + std::to_string(c.truth.mass()) +
                   (scaled_and_late ? ", scaled and late" : ", loaded controller"));
      EXPECT_GT(r.pairing.position_mismatch, 0.002);  // the tracking differs by what the issue saw and more
      EXPECT_LT(r.pairing.position_mismatch, 0.011);
      EXPECT_LT(r.pairing.mismatch_torque, 0.1);
      ExpectPayload(r, c.truth);
      EXPECT_NEAR(r.payload.mass(), c.truth.mass(), 0.01 * c.truth.mass());
    }
  }
}

TEST(PayloadIdentification, RefusesABaselineOfAnotherTrajectory) {
  const examples::BundledRobot arm = examples::Arm7();
  const RobotDynamics model = arm.Dynamics("payload@tool0");
  const Eigen::VectorXd x = Eigen::VectorXd::Zero(model.num_parameters());
  const JointSamples with = SimulateRun(model, x, 5, 6);
  const JointSamples other = SimulateRun(model, x, 7, 8);
  const double tolerance = PayloadIdentificationOptions().max_mismatch_torque;
  BaselinePairing pairing;
  try {
    PayloadDifferenceSamples(model, "tool0", with, other, tolerance, &pairing);
    ADD_FAILURE() << "a baseline of another trajectory was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("do not follow the same trajectory closely enough to be subtracted: "
                                         "paired at the best time shift ("),
              std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find("(at most 0.1: "), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("'s positions differ by "), std::string::npos) << e.what();
  }
  // The links' gravity torque between two excitations: many times the difference (measured 8.9),
  // nowhere near the tolerance; the positions tens of per cent of a range apart.
  EXPECT_GT(pairing.mismatch_torque, 10 * tolerance);
  EXPECT_GT(pairing.position_mismatch, 0.1);
  // The user may accept it anyway.
  EXPECT_NO_THROW(PayloadDifferenceSamples(model, "tool0", with, other, 1e3));
  // Joint effects do not belong in the difference's model, and the payload must be in it.
  EXPECT_THROW(PayloadDifferenceSamples(arm.Dynamics("viscous,payload@tool0"), "tool0", with, with, tolerance),
               std::invalid_argument);
  EXPECT_THROW(PayloadDifferenceSamples(model, "link3", with, with, tolerance), std::invalid_argument);
  // A time that does not increase, named with its log.
  JointSamples backwards = with;
  backwards.t[10] = backwards.t[9];
  try {
    PayloadDifferenceSamples(model, "tool0", with, backwards, tolerance);
    ADD_FAILURE() << "a baseline whose time does not increase was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()), "the baseline log's time does not increase at sample 10");
  }
}

}  // namespace
}  // namespace inertial
