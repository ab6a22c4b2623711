/// @file joint_limits.hpp
/// A robot's joint limits (URDF `<limit lower upper velocity effort>`), an excitation fitted inside
/// them, and the check of a joint log against them.
///
/// A Fourier excitation (fourier_trajectory.hpp) is linear in each joint's coefficient row: scaling
/// row j by s scales q_j - q0_j, qd_j and qdd_j by s. FitExcitationToLimits uses that to keep the
/// reference inside every joint's position range (centred in it) and below its velocity limit; the
/// effort a trajectory needs depends on the whole robot (gravity does not scale), so it is only
/// checked, on the simulated log, by FirstLimitViolation.
/// Conventions: SI units (rad or m, rad/s or m/s, N m or N); an absent limit is infinite.
#pragma once

#include <limits>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "inertial/model/fourier_trajectory.hpp"
#include "inertial/model/joint_samples.hpp"

namespace inertial {

/// One joint's limits; infinite where the model states none (a continuous joint's position).
struct JointLimits {
  double lower = -std::numeric_limits<double>::infinity();  ///< [rad or m]
  double upper = std::numeric_limits<double>::infinity();   ///< [rad or m], >= lower
  double velocity = std::numeric_limits<double>::infinity();  ///< |qd| bound [rad/s or m/s], > 0
  double effort = std::numeric_limits<double>::infinity();    ///< |tau| bound [N m or N], > 0
};

enum class LimitKind { kPosition, kVelocity, kEffort };
const char* ToString(LimitKind kind);  ///< "position", "velocity", "effort"

/// How FitExcitationToLimits changed one joint's excitation.
struct LimitedExcitation {
  int joint = 0;
  LimitKind kind = LimitKind::kPosition;  ///< the limit that bounded the scale
  double scale = 1.0;                     ///< factor applied to the joint's coefficients, in (0, 1)
};

/// Fits `trajectory` inside `limits` (one per joint) over the sample times `t`, keeping a fraction
/// `margin` of each limit free for the tracking error (0 <= margin < 1):
/// - q0_j: the middle of [lower, upper] when both are finite; with only a lower (upper) bound,
///   max(q0_j, lower + (1 + margin) E_j) (min(q0_j, upper - (1 + margin) E_j)) with E_j the joint's
///   largest excursion max_t |q_j(t) - q0_j|; with none, unchanged;
/// - then row j scaled by the largest s <= 1 with |q_j - q0_j| <= (1 - margin) (upper - lower) / 2
///   and |qd_j| <= (1 - margin) velocity at every t (maxima taken over t, so exact on the grid).
/// Returns the joints whose rows were scaled (s < 1), in joint order.
/// @throws std::invalid_argument if sizes differ, a limit is NaN, lower > upper, a velocity limit is
/// not positive, margin is outside [0, 1), or t is empty or not finite.
std::vector<LimitedExcitation> FitExcitationToLimits(const std::vector<JointLimits>& limits, const Eigen::VectorXd& t,
                                                     double margin, FourierTrajectory* trajectory);

/// The first sample (in time, then joint, then position / velocity / effort order) of `samples`
/// outside `limits` (one per joint: q in [lower, upper], |qd| <= velocity, |tau| <= effort).
struct LimitViolation {
  int joint = 0;
  LimitKind kind = LimitKind::kPosition;
  double time = 0.0;   ///< [s]
  double value = 0.0;  ///< q, qd or tau there
  double limit = 0.0;  ///< the bound it crossed (lower or upper for a position; the +- bound otherwise)
};
/// @throws std::invalid_argument if the number of limits is not the number of columns of samples.
std::optional<LimitViolation> FirstLimitViolation(const JointSamples& samples, const std::vector<JointLimits>& limits);

}  // namespace inertial
