#include "inertial/model/fourier_trajectory.hpp"

#include <cmath>
#include <random>
#include <stdexcept>
#include <string>

namespace inertial {
namespace {

constexpr double kTwoPi = 6.283185307179586476925286766559;

void Validate(const FourierTrajectory& traj) {
  if (!std::isfinite(traj.base_frequency_hz) || traj.base_frequency_hz <= 0.0) {
    throw std::invalid_argument("Fourier trajectory: base frequency must be positive and finite, got " +
                                std::to_string(traj.base_frequency_hz) + " Hz");
  }
  const Eigen::Index n = traj.q0.size();
  if (traj.a.rows() != n || traj.b.rows() != n || traj.a.cols() != traj.b.cols() || traj.a.cols() < 1) {
    throw std::invalid_argument("Fourier trajectory: a and b must both be (joints x harmonics) with " +
                                std::to_string(n) + " rows (q0's size) and at least one column; got a " +
                                std::to_string(traj.a.rows()) + "x" + std::to_string(traj.a.cols()) + ", b " +
                                std::to_string(traj.b.rows()) + "x" + std::to_string(traj.b.cols()));
  }
}

// Uniform on [-1, 1) from the top 53 bits: the same numbers on every standard library.
double UniformSymmetric(std::mt19937_64& gen) {
  return 2.0 * (static_cast<double>(gen() >> 11) * 0x1.0p-53) - 1.0;
}

}  // namespace

JointTrajectoryPoint FourierTrajectory::Evaluate(double t) const {
  Validate(*this);
  if (!std::isfinite(t)) throw std::invalid_argument("Fourier trajectory: time is not finite");
  const int K = num_harmonics();
  const double wf = kTwoPi * base_frequency_hz;
  Eigen::VectorXd w(K), s(K), c(K);
  for (int k = 0; k < K; ++k) {
    w[k] = wf * (k + 1);
    s[k] = std::sin(w[k] * t);
    c[k] = std::cos(w[k] * t);
  }
  JointTrajectoryPoint p;
  p.q = q0 + a * s.cwiseQuotient(w) - b * c.cwiseQuotient(w);
  p.qd = a * c + b * s;
  p.qdd = b * w.cwiseProduct(c) - a * w.cwiseProduct(s);
  return p;
}

Eigen::VectorXd FourierTrajectory::AmplitudeBound() const {
  Validate(*this);
  const double wf = kTwoPi * base_frequency_hz;
  Eigen::VectorXd bound = Eigen::VectorXd::Zero(num_joints());
  for (int j = 0; j < num_joints(); ++j) {
    for (int k = 0; k < num_harmonics(); ++k) bound[j] += std::hypot(a(j, k), b(j, k)) / (wf * (k + 1));
  }
  return bound;
}

FourierTrajectory RandomFourierTrajectory(int n_joints, int harmonics, double base_frequency_hz, double amplitude,
                                          std::uint64_t seed) {
  if (n_joints < 1 || harmonics < 1) {
    throw std::invalid_argument("random Fourier trajectory: need at least one joint and one harmonic, got " +
                                std::to_string(n_joints) + " joints and " + std::to_string(harmonics) +
                                " harmonics");
  }
  if (!std::isfinite(amplitude) || amplitude <= 0.0) {
    throw std::invalid_argument("random Fourier trajectory: amplitude must be positive and finite, got " +
                                std::to_string(amplitude));
  }
  FourierTrajectory traj;
  traj.base_frequency_hz = base_frequency_hz;
  traj.q0 = Eigen::VectorXd::Zero(n_joints);
  traj.a.resize(n_joints, harmonics);
  traj.b.resize(n_joints, harmonics);
  std::mt19937_64 gen(seed);
  for (int j = 0; j < n_joints; ++j) {
    for (int k = 0; k < harmonics; ++k) {
      traj.a(j, k) = UniformSymmetric(gen);
      traj.b(j, k) = UniformSymmetric(gen);
    }
  }
  const Eigen::VectorXd bound = traj.AmplitudeBound();  // validates the frequency
  for (int j = 0; j < n_joints; ++j) {
    if (bound[j] > 0.0) {
      traj.a.row(j) *= amplitude / bound[j];
      traj.b.row(j) *= amplitude / bound[j];
    }
  }
  return traj;
}

}  // namespace inertial
