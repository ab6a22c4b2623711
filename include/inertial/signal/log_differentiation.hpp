/// @file log_differentiation.hpp
/// The preprocessing stage of a recorded log (a whole joint log at once): the velocities and
/// accelerations its source did not measure, from its positions by Savitzky-Golay
/// (savitzky_golay.hpp). Non-causal, so better than the stream's causal filter
/// (stream_preprocessor.hpp), and only for logs. Readers (formats/joint_csv.hpp) only read and say
/// what is missing; this derives it.
#pragma once

#include "inertial/signal/savitzky_golay.hpp"
#include "inertial/model/joint_samples.hpp"

namespace inertial {

/// Replaces log->qd (if `velocities`) and log->qdd (if `accelerations`) by the first and second
/// derivative of one Savitzky-Golay fit of log->q; nothing if neither is asked for.
/// @throws std::invalid_argument saying why: the fit cannot be made (savitzky_golay.hpp: too few
///   samples for the order, a bad window), or a derivative is not finite (finite positions can
///   still overflow over very short steps), naming the sample and its time.
void DeriveFromPositions(JointSamples* log, bool velocities, bool accelerations, const SavitzkyGolayOptions& options);

}  // namespace inertial
