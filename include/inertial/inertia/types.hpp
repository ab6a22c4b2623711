/// @file types.hpp
/// Fixed-size Eigen aliases and the named indices of the 10-vectors used everywhere.
///
/// Conventions (the whole project):
/// - pi = [m, hx, hy, hz, Ixx, Iyy, Izz, Ixy, Iyz, Ixz]  (Rucker & Wensing 2022, eq. 3)
///   h = m c is the first mass moment, c the center of mass, both in the body frame B.
///   Ixx..Ixz are entries of the 3x3 rotational inertia about the origin of B, expressed in B;
///   Ixy is the (0,1) entry of that tensor, i.e. minus the integral of x*y*rho (eq. 1).
/// - theta = [alpha, d1, d2, d3, s12, s23, s13, t1, t2, t3]  (log-Cholesky, eq. 8-9 order).
/// - Spatial vectors angular first: twist [omega; v], wrench [moment; force].
/// - SI units: kg, m, kg m^2, s.
#pragma once

#include <Eigen/Core>

namespace inertial {

using Vector3 = Eigen::Matrix<double, 3, 1>;
using Vector4 = Eigen::Matrix<double, 4, 1>;
using Vector6 = Eigen::Matrix<double, 6, 1>;
using Vector10 = Eigen::Matrix<double, 10, 1>;
using Matrix3 = Eigen::Matrix<double, 3, 3>;
using Matrix4 = Eigen::Matrix<double, 4, 4>;
using Matrix6 = Eigen::Matrix<double, 6, 6>;
using Matrix10 = Eigen::Matrix<double, 10, 10>;
using Matrix6x10 = Eigen::Matrix<double, 6, 10>;

/// Indices into pi (eq. 3). Use these names, never bare numbers.
namespace pi_index {
inline constexpr int kMass = 0;
inline constexpr int kHx = 1;
inline constexpr int kHy = 2;
inline constexpr int kHz = 3;
inline constexpr int kIxx = 4;
inline constexpr int kIyy = 5;
inline constexpr int kIzz = 6;
inline constexpr int kIxy = 7;
inline constexpr int kIyz = 8;
inline constexpr int kIxz = 9;
}  // namespace pi_index

/// Indices into theta (eq. 8-9).
namespace theta_index {
inline constexpr int kAlpha = 0;
inline constexpr int kD1 = 1;
inline constexpr int kD2 = 2;
inline constexpr int kD3 = 3;
inline constexpr int kS12 = 4;
inline constexpr int kS23 = 5;
inline constexpr int kS13 = 6;
inline constexpr int kT1 = 7;
inline constexpr int kT2 = 8;
inline constexpr int kT3 = 9;
}  // namespace theta_index

/// Skew-symmetric matrix S(x) with S(x) y = x cross y (the paper's S, eq. 2).
inline Matrix3 Skew(const Vector3& x) {
  Matrix3 S;
  S << 0.0, -x.z(), x.y(),  //
      x.z(), 0.0, -x.x(),   //
      -x.y(), x.x(), 0.0;
  return S;
}

}  // namespace inertial
