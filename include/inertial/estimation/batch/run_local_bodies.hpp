/// @file run_local_bodies.hpp
/// Several recorded runs fitted as one model (eq. 14) where a body was present in one run only: a
/// payload the robot carried in that run, whose mass may be known and its COM and inertia not. Such
/// a body is a payload with a block of A of its own (EffectSpec::own_features): in the run that
/// carried it, its columns are its link's (it moves with the link); in every other run they are
/// zero. The data term stays a sum of squared torque errors over every sample,
///
///   sum_runs r  sum_{k in r} || A_k^(r) w(x) - tau_k ||^2,   A^(r): the own blocks of bodies not in r zeroed,
///
/// so its statistics are the sum over runs of each run's own (AccumulateNormalEquations), with the
/// rows and columns of the bodies absent from that run zeroed (exactly the statistics of A^(r)).
/// The fit is then IdentifyJointModel's, with everything shared (links, rotors, joint effects)
/// seen by every run and each run's body by its own run: the paper's regularized problem with one
/// more body, log-Cholesky as every other, so it is physically consistent at every iterate. A known
/// mass is held exactly by holding that body's alpha (JointIdentificationOptions::held_parameters).
#pragma once

#include <vector>

#include "inertial/estimation/batch/gain_identification.hpp"
#include "inertial/estimation/batch/joint_identification.hpp"

namespace inertial {

/// The statistics of the same samples with features [first, first + count) zero: those rows and
/// columns of A^T A (and of every A^T A in a GainProblem) and those entries of A^T b (A^T y) zeroed.
void ZeroFeatures(int first, int count, JointNormalEquations* eq);
void ZeroFeatures(int first, int count, GainProblem* problem);

/// Adds statistics of further samples of the same model (and gain joints) to *sum; a
/// default-constructed *sum (no features) takes `more` as it is.
/// @throws std::invalid_argument if the sizes or the gain joints differ.
void AddStatistics(const JointNormalEquations& more, JointNormalEquations* sum);
void AddStatistics(const GainProblem& more, GainProblem* sum);

/// body_runs: one entry per estimated body of `model`: the index into `runs` of the only run it was
/// present in, or -1 for a body of every run (links, rotors, payloads carried throughout).
/// @throws std::invalid_argument if body_runs has the wrong size, names a run that does not exist,
/// or gives a run to a body without a block of its own (its columns are its link's, shared by
/// every run); and as AccumulateNormalEquations.
JointNormalEquations AccumulateRunNormalEquations(const RobotDynamics& model, const std::vector<JointSamples>& runs,
                                                  const std::vector<int>& body_runs);

/// The same for a fit with gains (gain_identification.hpp): known[r] the known torques of run r
/// (empty: none). @throws as above and as AccumulateGainProblem.
GainProblem AccumulateRunGainProblem(const RobotDynamics& model, const std::vector<JointSamples>& runs,
                                     const std::vector<Eigen::MatrixXd>& known, const std::vector<int>& gain_dofs,
                                     const std::vector<int>& body_runs);

}  // namespace inertial
