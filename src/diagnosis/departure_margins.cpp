#include "inertial/diagnosis/departure_margins.hpp"

#include <cmath>
#include <limits>

namespace inertial {

DepartureMargins DepartureMarginsOf(const InertialParams& prior, const BodyUncertainty& std,
                                    const Matrix10& pi_covariance) {
  DepartureMargins margins;
  margins.mass = kDepartureMargin * std.mass;
  Eigen::Matrix<double, 3, 10> T = Eigen::Matrix<double, 3, 10>::Zero();
  T.col(0) = -prior.com();
  T.block<3, 3>(0, 1).setIdentity();
  margins.first_moment = kDepartureMargin * kDepartureMargin * T * pi_covariance * T.transpose();
  margins.inertia_about_com = kDepartureMargin * std.inertia_about_com;
  if (!std::isfinite(std.mass) || !std.com.allFinite()) {
    margins.first_moment = std::numeric_limits<double>::infinity() * Matrix3::Identity();
  }
  return margins;
}

}  // namespace inertial
