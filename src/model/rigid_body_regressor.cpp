#include "inertial/model/rigid_body_regressor.hpp"

#include <Eigen/Geometry>

namespace inertial {

Eigen::Matrix<double, 3, 6> InertiaTimesVectorMap(const Vector3& x) {
  Eigen::Matrix<double, 3, 6> L;
  //   Ixx    Iyy    Izz    Ixy    Iyz    Ixz
  L << x[0], 0.0, 0.0, x[1], 0.0, x[2],  //
      0.0, x[1], 0.0, x[0], x[2], 0.0,   //
      0.0, 0.0, x[2], 0.0, x[1], x[0];
  return L;
}

Matrix6x10 RigidBodyRegressor(const Vector6& xi, const Vector6& xi_dot, const Vector3& g_B) {
  // With p = I xi = [n; f], n = I_o omega + h x v, f = m v + omega x h, eq. (12) expands to
  //   moment = I_o alpha + omega x (I_o omega) + h x a + omega x (h x v) + v x (omega x h)
  //   force  = m (a + omega x v) + alpha x h + omega x (omega x h)
  // with alpha = d(omega)/dt, a = dv/dt - g (gravity as a frame acceleration).
  const Vector3 omega = xi.head<3>();
  const Vector3 v = xi.tail<3>();
  const Vector3 alpha = xi_dot.head<3>();
  const Vector3 a = xi_dot.tail<3>() - g_B;
  Matrix6x10 Y = Matrix6x10::Zero();
  // m
  Y.block<3, 1>(3, pi_index::kMass) = a + omega.cross(v);
  // h: moment h x a + omega x (h x v) + v x (omega x h) = (-S(a) - S(omega) S(v) + S(v) S(omega)) h
  //    = S(v x omega - a) h, as S(x) S(y) - S(y) S(x) = S(x x y)
  Y.block<3, 3>(0, pi_index::kHx) = Skew(v.cross(omega) - a);
  //    force alpha x h + omega x (omega x h) = (S(alpha) + S(omega)^2) h, S(omega)^2 = omega omega^T - |omega|^2 1,
  //    its diagonal -(omega_y^2 + omega_z^2), ... written as such (no cancellation when one component dominates)
  Y.block<3, 3>(3, pi_index::kHx) = Skew(alpha) + omega * omega.transpose();
  const Vector3 w2 = omega.cwiseProduct(omega);
  Y(3, pi_index::kHx) = -(w2[1] + w2[2]);
  Y(4, pi_index::kHx + 1) = -(w2[0] + w2[2]);
  Y(5, pi_index::kHx + 2) = -(w2[0] + w2[1]);
  // rotational inertia: I_o alpha + omega x (I_o omega), column by column of the maps
  // (InertiaTimesVectorMap), each omega x (column of the map of omega)
  const Eigen::Matrix<double, 3, 6> L_alpha = InertiaTimesVectorMap(alpha), L_omega = InertiaTimesVectorMap(omega);
  for (int k = 0; k < 6; ++k) {
    Y.block<3, 1>(0, pi_index::kIxx + k) = L_alpha.col(k) + omega.cross(Vector3(L_omega.col(k)));
  }
  return Y;
}

}  // namespace inertial
