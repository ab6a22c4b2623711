#include "inertial/inertia/nearest_consistent.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>

#include "inertial/inertia/consistency.hpp"

namespace inertial {

bool NearestConsistentBody(const InertialParams& body, InertialParams* repaired, std::string* why) {
  if (!body.AllFinite()) {
    if (why != nullptr) *why = "a number is not finite";
    return false;
  }
  const double m = body.mass();
  if (!(m > 0.0)) {
    if (why != nullptr) *why = "mass is not positive, so there is no centre of mass to keep";
    return false;
  }
  if (CheckConsistency(body).fully_consistent()) {
    *repaired = body;
    return true;
  }
  const Vector3 c = body.com();
  const Matrix3 I_c = body.rotational_inertia_about_com();
  const Matrix3 Sigma_c = 0.5 * I_c.trace() * Matrix3::Identity() - I_c;
  const Eigen::SelfAdjointEigenSolver<Matrix3> eig(Sigma_c);
  const double eps = std::max(1e-3 * eig.eigenvalues().maxCoeff(), m * 1e-6);
  const Vector3 sigma = eig.eigenvalues().cwiseMax(eps);
  const Matrix3 Sigma = eig.eigenvectors() * sigma.asDiagonal() * eig.eigenvectors().transpose();
  const Matrix3 I_new = Sigma.trace() * Matrix3::Identity() - Sigma;
  *repaired = InertialParams::FromMassComInertia(m, c, I_new);
  if (why != nullptr) why->clear();
  return true;
}

}  // namespace inertial
