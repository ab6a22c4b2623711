/// @file trajectory_overlap.hpp
/// Whether held-out data retrace the training excitation, so that they cannot reveal overfitting.
///
/// A validation log that repeats the training trajectory (a periodic Fourier excitation run
/// again, or the last part of one periodic log held out from its first part) meets, at every
/// instant, a state the fit has already seen: an effect that only fits that excitation (a spring
/// imitating a residual that depends on where the trajectory is at each time) predicts it as well
/// as the training data, and the held-out error rewards it. Detection: the share of held-out
/// samples whose state (q, qd) lies within `tolerance` of some training sample in every
/// coordinate, each coordinate measured relative to its range over both logs. With the default 1 %
/// of the range in all 2n coordinates, a different excitation of a robot with two or more joints
/// comes that close on a few per cent of its samples (a curve in 2n dimensions rarely meets
/// another); one retraced within a few milliradians meets it on nearly all. A single joint's (q, qd)
/// plane is two-dimensional and a long trajectory fills part of it, hence the bound of 0.8 of the
/// held-out samples before the logs are called repeats.
#pragma once

#include "inertial/model/joint_samples.hpp"

namespace inertial {

inline constexpr double kRetraceTolerance = 0.01;  ///< of each coordinate's range
inline constexpr double kRetracedShare = 0.8;     ///< held-out share above which the logs repeat

/// The share (0..1) of `other`'s samples (at most 500, evenly spaced) within `tolerance` of a
/// sample of `reference` (at most 20000, evenly spaced) in every coordinate of (q, qd).
/// @throws std::invalid_argument if either log is empty or their joints differ.
double RetracedShare(const JointSamples& reference, const JointSamples& other, double tolerance = kRetraceTolerance);

}  // namespace inertial
