#include "inertial/inertia/closed_form_bodies.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace inertial {
namespace {

void RequirePositive(const char* body, const char* what, double value) {
  if (!(std::isfinite(value) && value > 0.0)) {
    std::ostringstream os;
    os << body << ": " << what << " must be positive and finite, got " << value;
    throw std::invalid_argument(os.str());
  }
}

}  // namespace

InertialParams BodyFromSecondMoments(double mass, const Vector3& L, const Pose& pose) {
  const Matrix3 D = Vector3(L.y() + L.z(), L.x() + L.z(), L.x() + L.y()).asDiagonal();
  const Matrix3 I_Ccm_B = pose.R_BC * D * pose.R_BC.transpose();
  return InertialParams::FromMassComInertia(mass, pose.p_BoCo_B, I_Ccm_B);
}

InertialParams SolidBox(double mass, double size_x, double size_y, double size_z, const Pose& pose) {
  RequirePositive("box", "mass", mass);
  RequirePositive("box", "size_x", size_x);
  RequirePositive("box", "size_y", size_y);
  RequirePositive("box", "size_z", size_z);
  return BodyFromSecondMoments(mass, mass / 12.0 * Vector3(size_x * size_x, size_y * size_y, size_z * size_z), pose);
}

InertialParams SolidCylinder(double mass, double radius, double length, const Pose& pose) {
  RequirePositive("cylinder", "mass", mass);
  RequirePositive("cylinder", "radius", radius);
  RequirePositive("cylinder", "length", length);
  const double r2 = radius * radius;
  return BodyFromSecondMoments(mass, mass * Vector3(r2 / 4.0, r2 / 4.0, length * length / 12.0), pose);
}

InertialParams SolidSphere(double mass, double radius, const Pose& pose) {
  RequirePositive("sphere", "mass", mass);
  RequirePositive("sphere", "radius", radius);
  return BodyFromSecondMoments(mass, Vector3::Constant(mass * radius * radius / 5.0), pose);
}

InertialParams SolidEllipsoid(double mass, double semi_axis_x, double semi_axis_y, double semi_axis_z,
                              const Pose& pose) {
  RequirePositive("ellipsoid", "mass", mass);
  RequirePositive("ellipsoid", "semi_axis_x", semi_axis_x);
  RequirePositive("ellipsoid", "semi_axis_y", semi_axis_y);
  RequirePositive("ellipsoid", "semi_axis_z", semi_axis_z);
  const Vector3 a2(semi_axis_x * semi_axis_x, semi_axis_y * semi_axis_y, semi_axis_z * semi_axis_z);
  return BodyFromSecondMoments(mass, mass / 5.0 * a2, pose);
}

}  // namespace inertial
