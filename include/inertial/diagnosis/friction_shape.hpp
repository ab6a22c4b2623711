/// @file friction_shape.hpp
/// The shape of a joint's friction, fitted to what a model leaves unexplained.
///
/// Coulomb friction smoothed by tanh(qd / v_s), its asymmetric form and the sigmoid of Gaz et al.
/// (RA-L 2019, eq. 8; joint_effect.hpp) are linear in their levels but not in their shape: the
/// velocity scale v_s, the sigmoid's steepness p2 and shift p3. A real arm's friction rises over a
/// velocity range set by its gearing and lubricant (a few mrad/s on a harmonic drive, tenths of a
/// rad/s on a belt), so one fixed v_s misses it, and a wrong v_s leaves a residual that other
/// effects (viscous friction, a spring) are then picked to imitate.
///
/// The shape is chosen by profile least squares on the residual r of a model holding the links,
/// viscous friction and an offset on every joint: for each shape on a grid, the reduction of
/// ||r||^2 that adding the effect's features would bring, with the features first made orthogonal
/// to that joint's viscous (qd) and offset (1) features (the residual already is, to first order:
/// the model that left it holds them) and every level non-negative. The grid is relative to the
/// joint's own velocity RMS (so it holds for revolute and prismatic joints and for slow and fast
/// excitations): v_s = rms(qd) 2^-k for k = 1..10, from half the RMS (nearly viscous) to 1/1000 of
/// it (a step, below any encoder's velocity resolution at the speeds of an identification run);
/// p2 = 2 / v_s on the same grid (the sigmoid of zero shift is Coulomb friction of scale 2 / p2)
/// and p2 p3 in {-2, -1, -1/2, 0, 1/2, 1, 2} (up to a 0.88 / 0.12 split of the levels between the
/// two directions). The levels themselves are fitted later with everything else; the shape counts
/// as fitted parameters when the diagnosis weighs the effect (candidate_evidence.hpp).
#pragma once

#include <Eigen/Core>

#include "inertial/model/joint_effect.hpp"

namespace inertial {

struct FrictionShape {
  EffectSpec spec;    ///< kind and target as asked, the fitted scale (or steepness and shift) set
  double gain = 0.0;  ///< the fall of ||r||^2 with the effect's levels fitted (0: none helps)
};

/// Fits the shape of a `kind` (coulomb, asymmetric or sigmoid) friction on joint `joint` to the
/// residual `residual` (measured minus modelled torque) at velocities `qd` (same length, >= 3).
/// @throws std::invalid_argument for another kind, sizes that differ, or non-finite values.
FrictionShape FitFrictionShape(EffectKind kind, const std::string& joint, const Eigen::VectorXd& qd,
                               const Eigen::VectorXd& residual);

/// Parameters the shape adds to the effect's levels: 1 for coulomb and asymmetric (v_s), 2 for
/// sigmoid (p2, p3), 0 for every other kind.
int FrictionShapeParameters(EffectKind kind);

}  // namespace inertial
