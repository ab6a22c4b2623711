/// @file fourier_trajectory.hpp
/// The finite Fourier series excitation trajectory (Swevers, Ganseman, Tukel, De Schutter &
/// Van Brussel, IEEE T-RA 1997): for every joint j, with w_f = 2 pi f_f,
///
///   q_j(t)   = q0_j + sum_{k=1..K} a_jk / (w_f k) sin(w_f k t) - b_jk / (w_f k) cos(w_f k t)
///   qd_j(t)  =        sum_{k=1..K} a_jk cos(w_f k t) + b_jk sin(w_f k t)
///   qdd_j(t) =        sum_{k=1..K} w_f k (b_jk cos(w_f k t) - a_jk sin(w_f k t)),
///
/// periodic with period 1 / f_f. Since a sin(x) - b cos(x) = sqrt(a^2 + b^2) sin(x - phase),
///   |q_j(t) - q0_j| <= sum_k sqrt(a_jk^2 + b_jk^2) / (w_f k)   (AmplitudeBound) for all t.
/// Conventions: SI units (rad for revolute, m for prismatic joints); f_f in Hz; t in seconds.
#pragma once

#include <cstdint>

#include <Eigen/Core>

namespace inertial {

/// Joint positions, velocities and accelerations at one instant (size: the number of joints).
struct JointTrajectoryPoint {
  Eigen::VectorXd q, qd, qdd;
};

struct FourierTrajectory {
  double base_frequency_hz = 0.1;  ///< f_f [Hz]; w_f = 2 pi f_f
  Eigen::VectorXd q0;              ///< offsets, one per joint
  Eigen::MatrixXd a, b;            ///< coefficients, joints x harmonics (row j, column k-1)

  int num_joints() const { return static_cast<int>(q0.size()); }
  int num_harmonics() const { return static_cast<int>(a.cols()); }
  double period() const { return 1.0 / base_frequency_hz; }  ///< [s]

  /// q, qd, qdd at time t (closed form).
  /// @throws std::invalid_argument if a and b are not both num_joints() x K, K >= 1, the base
  /// frequency is not positive and finite, or t is not finite.
  JointTrajectoryPoint Evaluate(double t) const;

  /// Per joint: sum_k sqrt(a_jk^2 + b_jk^2) / (w_f k), a bound on |q_j(t) - q0_j| for every t.
  /// @throws std::invalid_argument as Evaluate.
  Eigen::VectorXd AmplitudeBound() const;
};

/// A random trajectory, deterministic for a seed (std::mt19937_64 with a portable uniform mapping):
/// a_jk, b_jk uniform on [-1, 1], then every joint's row scaled so that AmplitudeBound() equals
/// amplitude, hence |q_j(t) - q0_j| <= amplitude for all t. q0 = 0 (set it afterwards if needed).
/// @throws std::invalid_argument if n_joints or harmonics is < 1, or the frequency or amplitude is
/// not positive and finite.
FourierTrajectory RandomFourierTrajectory(int n_joints, int harmonics, double base_frequency_hz, double amplitude,
                                          std::uint64_t seed);

}  // namespace inertial
