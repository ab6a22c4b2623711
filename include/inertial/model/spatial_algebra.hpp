/// @file spatial_algebra.hpp
/// 6D spatial vector operations (Featherstone 2008), angular first: twist xi = [omega; v],
/// wrench w = [moment; force], both in body coordinates. SI units.
#pragma once

#include "inertial/inertia/types.hpp"

namespace inertial {

/// xi x (motion cross product): [[S(omega), 0], [S(v), S(omega)]].
inline Matrix6 MotionCross(const Vector6& xi) {
  Matrix6 X = Matrix6::Zero();
  const Matrix3 Sw = Skew(xi.head<3>());
  X.block<3, 3>(0, 0) = Sw;
  X.block<3, 3>(3, 0) = Skew(xi.tail<3>());
  X.block<3, 3>(3, 3) = Sw;
  return X;
}

/// xi x* (force cross product, the paper's eq. 12): [[S(omega), S(v)], [0, S(omega)]] = -(xi x)^T.
inline Matrix6 ForceCross(const Vector6& xi) {
  Matrix6 X = Matrix6::Zero();
  const Matrix3 Sw = Skew(xi.head<3>());
  X.block<3, 3>(0, 0) = Sw;
  X.block<3, 3>(0, 3) = Skew(xi.tail<3>());
  X.block<3, 3>(3, 3) = Sw;
  return X;
}

}  // namespace inertial
