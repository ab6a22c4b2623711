/// @file body_torques.hpp
/// The joint torques one estimated body of a robot model causes, at its prior: its pi through the
/// joint-torque regressor block of the tree body it is fixed to (robot_dynamics.hpp). What a known
/// payload adds to a run's torques (signal/recorded_runs.hpp: a run recorded carrying it), so that
/// a fit of the robot can take it out of that run's measurements.
#pragma once

#include "inertial/model/joint_samples.hpp"
#include "inertial/model/robot_dynamics.hpp"

namespace inertial {

/// Rows = samples, columns = DOFs: Y_b(q, qd, qdd) pi_e for body e of `model` at its prior, where b
/// is e's tree body (gravity included, as the model's). @throws std::invalid_argument if e is not a
/// body of the model or the samples do not fit the model's DOFs.
Eigen::MatrixXd BodyTorques(const RobotDynamics& model, int e, const JointSamples& data);

}  // namespace inertial
