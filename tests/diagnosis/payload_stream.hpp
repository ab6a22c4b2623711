/// @file payload_stream.hpp
/// A simulated pick and place on the 7-DOF arm's last link for the payload events' tests
/// (tests/diagnosis/payload_event_test.cpp, the daemon's in tests/runtime): the arm as built (its
/// links perturbed from the URDF), a Fourier excitation with exact q, qd, qdd, and the torque of the
/// true arm, with the payload during [pick_time, place_time), plus Gaussian noise.
#pragma once

#include <cmath>
#include <random>
#include <vector>

#include "../../examples/bundled_robots.hpp"
#include "inertial/inertia/closed_form_bodies.hpp"
#include "inertial/model/fourier_trajectory.hpp"
#include "inertial/model/joint_samples.hpp"
#include "test_support.hpp"

namespace inertial::testing {

inline constexpr int kLink7 = 6;

struct Scenario {
  double rate_hz = 500;
  double duration = 60;
  double pick_time = 20, place_time = 40;  // payload on link7 during [pick_time, place_time)
  double payload_mass = 2.0;
  Vector3 payload_com = Vector3(0.02, 0.0, 0.10);  // in link7's frame: 5.5 cm beyond the flange
  double sigma_tau = 0.1;                          // torque noise [N m]
  std::uint64_t seed = 7;
};

inline RobotDynamics ArmModel() { return examples::Arm7().Dynamics(""); }

inline InertialParams Payload(const Scenario& s) {
  return SolidSphere(s.payload_mass, 0.04, Pose{Matrix3::Identity(), s.payload_com});
}

// The arm as built (every link's theta in [-0.1, 0.1]: masses within about +-20 % of the URDF).
inline Eigen::VectorXd ArmTruth(const RobotDynamics& model, std::uint64_t seed) {
  Rng rng(static_cast<unsigned>(seed));
  Eigen::VectorXd x = Eigen::VectorXd::Zero(model.num_parameters());
  for (int i = 0; i < x.size(); ++i) x[i] = rng.Uniform(-0.1, 0.1);
  return x;
}

// The truth with the payload on link7.
inline Eigen::VectorXd LoadedTruth(const RobotDynamics& model, const Eigen::VectorXd& x, const InertialParams& payload) {
  Eigen::VectorXd loaded = x;
  const EstimatedBody& link7 = model.bodies()[kLink7];
  const InertialParams body = InertialParams::FromVector(link7.map.ToPi(x.segment<10>(10 * kLink7))) + payload;
  loaded.segment<10>(10 * kLink7) = link7.map.ThetaOf(body);
  return loaded;
}

struct Stream {
  std::vector<JointSample> samples;
  std::vector<double> payload_rms;  // per sample: RMS over the joints of the payload's torque [N m]
};

// A Fourier excitation (5 harmonics, 0.1 Hz base, +-0.8 rad) about a working pose (elbow bent), q,
// qd, qdd exact; tau of the true arm (with the payload during [pick, place)) plus Gaussian noise.
inline Stream MakeStream(const RobotDynamics& model, const Eigen::VectorXd& x_true, const Scenario& s, bool with_payload) {
  FourierTrajectory ref = RandomFourierTrajectory(7, 5, 0.1, 0.8, s.seed);
  ref.q0 = (Eigen::VectorXd(7) << 0, 0.6, 0, -1.2, 0, 0.6, 0).finished();
  const Eigen::VectorXd w_empty = model.Coefficients(x_true);
  const Eigen::VectorXd w_loaded = model.Coefficients(LoadedTruth(model, x_true, Payload(s)));
  std::mt19937_64 gen(s.seed + 1);
  std::normal_distribution<double> noise(0.0, s.sigma_tau);
  Stream out;
  const int count = static_cast<int>(std::lround(s.duration * s.rate_hz));
  for (int i = 0; i <= count; ++i) {
    JointSample js;
    js.t = i / s.rate_hz;
    const JointTrajectoryPoint p = ref.Evaluate(js.t);
    js.q = p.q;
    js.qd = p.qd;
    js.qdd = p.qdd;
    const Eigen::VectorXd tau0 = model.InverseDynamicsFromCoefficients(w_empty, p.q, p.qd, p.qdd);
    const Eigen::VectorXd tau1 = model.InverseDynamicsFromCoefficients(w_loaded, p.q, p.qd, p.qdd);
    const bool loaded = with_payload && js.t >= s.pick_time && js.t < s.place_time;
    js.tau = loaded ? tau1 : tau0;
    for (int j = 0; j < 7; ++j) js.tau[j] += noise(gen);
    out.payload_rms.push_back((tau1 - tau0).norm() / std::sqrt(7.0));
    out.samples.push_back(std::move(js));
  }
  return out;
}

}  // namespace inertial::testing
