#include "inertial/inertia/consistency.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace inertial {

namespace {

// Appends one failed condition to the report's reason, separated from the earlier ones by "; ".
void AddReason(std::ostringstream& why, const std::string& s) {
  if (why.tellp() > 0) why << "; ";
  why << s;
}

// Checks the rotational inertia at the COM (positive definite, triangle inequalities) for a body of
// positive mass; origin_scale is the largest eigenvalue magnitude of the inertia about the origin.
void CheckComConditions(const InertialParams& body, double relative_tolerance, double origin_scale,
                        ConsistencyReport& r, std::ostringstream& why) {
  const Eigen::SelfAdjointEigenSolver<Matrix3> eig_com(body.rotational_inertia_about_com(), Eigen::EigenvaluesOnly);
  const Vector3 D = eig_com.eigenvalues();  // ascending
  r.principal_moments_com = D;
  r.min_inertia_eigenvalue_com = D[0];
  // With D ascending, the binding inequality is D0 + D1 - D2 (the others are then >= it only if
  // all D are >= 0, so take the minimum of all three explicitly).
  const double t0 = D[1] + D[2] - D[0];
  const double t1 = D[0] + D[2] - D[1];
  const double t2 = D[0] + D[1] - D[2];
  r.min_triangle_margin = std::min({t0, t1, t2});
  // The moments at the COM come from those at the origin less m c c^T: their rounding is relative
  // to the origin's inertia, not to D itself (a point mass away from the origin has D of pure
  // rounding noise, whose sign differs between x86 and Arm). So the scale is the larger of the two.
  const double scale = std::max({std::abs(D[2]), origin_scale, std::numeric_limits<double>::min()});
  r.inertia_positive_definite_com = D[0] > relative_tolerance * scale;
  r.triangle_inequalities = r.min_triangle_margin > relative_tolerance * scale;
  if (!r.inertia_positive_definite_com) {
    std::ostringstream os;
    os << "rotational inertia at the COM not positive definite: smallest principal moment " << D[0]
       << " kg m^2 is not above " << relative_tolerance << " x the largest (" << D[2] << " kg m^2)";
    AddReason(why, os.str());
  }
  if (!r.triangle_inequalities) {
    std::ostringstream os;
    os << "triangle inequality (eq. 4) violated at the COM: smallest of Dy+Dz-Dx, Dx+Dz-Dy, Dx+Dy-Dz is "
       << r.min_triangle_margin << " kg m^2, not above " << relative_tolerance
       << " x the largest principal moment (principal moments " << D[0] << ", " << D[1] << ", " << D[2]
       << " kg m^2)";
    AddReason(why, os.str());
  }
}

// Checks that the pseudo-inertia J is positive definite.
void CheckPseudoInertia(const InertialParams& body, double relative_tolerance, ConsistencyReport& r,
                        std::ostringstream& why) {
  const Eigen::SelfAdjointEigenSolver<Matrix4> eig_J(body.pseudo_inertia(), Eigen::EigenvaluesOnly);
  r.min_pseudo_inertia_eigenvalue = eig_J.eigenvalues()[0];
  const double J_scale = std::max(eig_J.eigenvalues().cwiseAbs().maxCoeff(), std::numeric_limits<double>::min());
  r.pseudo_inertia_positive_definite = r.min_pseudo_inertia_eigenvalue > relative_tolerance * J_scale;
  if (!r.pseudo_inertia_positive_definite) {
    std::ostringstream os;
    if (!eig_J.eigenvalues().allFinite()) {
      os << "pseudo-inertia J: eigenvalues overflow (entries too large for double precision)";
    } else {
      os << "pseudo-inertia J not positive definite: smallest eigenvalue " << r.min_pseudo_inertia_eigenvalue
         << " is not above " << relative_tolerance << " x the largest (" << eig_J.eigenvalues()[3] << ")";
    }
    AddReason(why, os.str());
  }
}

}  // namespace

ConsistencyReport CheckConsistency(const InertialParams& body, double relative_tolerance) {
  ConsistencyReport r;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  r.finite = body.AllFinite();
  r.mass = body.mass();
  if (!r.finite) {
    r.min_inertia_eigenvalue_origin = r.min_inertia_eigenvalue_com = r.min_triangle_margin = nan;
    r.min_pseudo_inertia_eigenvalue = nan;
    r.principal_moments_com.setConstant(nan);
    r.reason = "non-finite parameter (NaN or Inf) in pi";
    return r;
  }
  std::ostringstream why;

  r.mass_positive = r.mass > 0.0;
  if (!r.mass_positive) {
    std::ostringstream os;
    os << "mass not positive: m = " << r.mass << " kg";
    AddReason(why, os.str());
  }

  const Eigen::SelfAdjointEigenSolver<Matrix3> eig_origin(body.rotational_inertia_about_origin(),
                                                          Eigen::EigenvaluesOnly);
  r.min_inertia_eigenvalue_origin = eig_origin.eigenvalues()[0];
  const double origin_scale = std::max(std::abs(eig_origin.eigenvalues()[2]), std::numeric_limits<double>::min());
  r.inertia_positive_definite_origin = r.min_inertia_eigenvalue_origin > relative_tolerance * origin_scale;

  if (r.mass_positive) {
    CheckComConditions(body, relative_tolerance, origin_scale, r, why);
  } else {
    r.min_inertia_eigenvalue_com = r.min_triangle_margin = nan;
    r.principal_moments_com.setConstant(nan);
  }

  CheckPseudoInertia(body, relative_tolerance, r, why);
  r.reason = why.str();
  return r;
}

bool IsPhysicallyConsistent(const InertialParams& body, double relative_tolerance) {
  return CheckConsistency(body, relative_tolerance).fully_consistent();
}

}  // namespace inertial
