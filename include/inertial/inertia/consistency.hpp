/// @file consistency.hpp
/// Physical-consistency checks of an InertialParams, with margins (how far inside or outside each
/// condition the body is), not just a boolean.
///
/// Full physical consistency (Rucker & Wensing 2022, Def. II.1): some finite density rho >= 0 gives
/// pi through eq. (1) with m > 0. Equivalent conditions (Theorem II.1 and Wensing et al. 2018):
///  - m > 0, the rotational inertia at the COM positive definite, and its principal moments
///    satisfying the strict triangle inequalities (4);
///  - the 4x4 pseudo-inertia J is positive definite.
/// Degenerate bodies (point, line and plane masses) meet the inequalities only with equality and
/// are therefore not fully consistent.
///
/// Units: mass margin in kg; inertia margins in kg m^2; the pseudo-inertia eigenvalue in the
/// body's mixed units (kg m^2 and kg entries). Conventions as in inertial_params.hpp.
#pragma once

#include <string>

#include "inertial/inertia/inertial_params.hpp"

namespace inertial {

struct ConsistencyReport {
  bool finite = false;  ///< all ten numbers finite
  /// m [kg]: positive for a body.
  double mass = 0.0;
  /// Smallest eigenvalue of the rotational inertia about the frame origin, I_Bo_B [kg m^2] (the
  /// paper's I-bar; its positive definiteness is the classical, necessary-only condition).
  double min_inertia_eigenvalue_origin = 0.0;
  /// Smallest eigenvalue of the rotational inertia about the COM, I_Bcm_B [kg m^2] (NaN if m <= 0).
  double min_inertia_eigenvalue_com = 0.0;
  /// Principal moments D of I_Bcm_B, ascending [kg m^2] (NaN if m <= 0).
  Vector3 principal_moments_com = Vector3::Zero();
  /// min(Dy + Dz - Dx, Dx + Dz - Dy, Dx + Dy - Dz) at the COM [kg m^2] (eq. 4), equal to twice the
  /// smallest second moment L of eq. (5). NaN if m <= 0.
  double min_triangle_margin = 0.0;
  /// Smallest eigenvalue of the pseudo-inertia J.
  double min_pseudo_inertia_eigenvalue = 0.0;

  bool mass_positive = false;
  bool inertia_positive_definite_origin = false;
  bool inertia_positive_definite_com = false;
  bool triangle_inequalities = false;
  bool pseudo_inertia_positive_definite = false;

  /// Every condition holds: the body is fully physically consistent.
  bool fully_consistent() const {
    return finite && mass_positive && inertia_positive_definite_com && triangle_inequalities &&
           pseudo_inertia_positive_definite;
  }
  /// Empty when fully consistent; otherwise every failed condition with its margin, e.g.
  /// "triangle inequality violated at the COM: Dx + Dy - Dz = -0.02 kg m^2".
  std::string reason;
};

/// Checks every condition. A margin counts as positive only if it exceeds
/// relative_tolerance * scale, where scale is the largest principal moment at the COM or, if larger,
/// at the origin (inertia conditions: the COM's moments are the origin's less m c c^T and carry their
/// rounding), or the largest eigenvalue of J; so point, rod and plate bodies, whose margins are zero
/// up to rounding, are reported as not fully consistent on every machine. The mass must be > 0 (strictly).
ConsistencyReport CheckConsistency(const InertialParams& body, double relative_tolerance = 1e-12);

/// Short form: CheckConsistency(body).fully_consistent().
bool IsPhysicallyConsistent(const InertialParams& body, double relative_tolerance = 1e-12);

}  // namespace inertial
