/// @file explained_error.hpp
/// The score by which the diagnoses (joint_diagnosis.hpp, body_diagnosis.hpp) rank a candidate
/// effect: the share of the held-out mean-square error it removes, averaged over channels (joints,
/// or wrench components),
///
///   explained = mean_c (1 - rms_c(with)^2 / rms_c(without)^2),
///
/// so that every channel counts alike whatever its scale. Negative when the candidate made the
/// held-out error larger (overfitting); channels whose error is already zero count 0.
#pragma once

#include <Eigen/Core>

#include "inertial/estimation/batch/joint_identification.hpp"

namespace inertial {

/// @throws std::invalid_argument if the sizes differ or are zero.
double ExplainedShare(const Eigen::VectorXd& rms_without, const Eigen::VectorXd& rms_with);

/// Near-ties go to the simpler effect: candidates are ranked by explained - kParsimony * (p - 1)
/// for p parameters, so a spring (k, q0) that explains no more than an offset (a spring of tiny k
/// and large q0 is one) ranks below it. Suggestions still need explained >= the threshold.
inline constexpr double kParsimony = 0.005;
inline double RankingKey(double explained, int parameters) { return explained - kParsimony * (parameters - 1); }

/// Whether the held-out data support a candidate, beyond its score: (a) explained >= min_explained;
/// (b) the pooled held-out mean-square error falls (a candidate that helps small channels while
/// hurting the others is not suggested); (c) on some channel the held-out RMS falls by at least
/// min_gain of that channel's measured RMS (so the tiny residual a regularized fit leaves on
/// noise-free data, or the rounding of the normal equations, is not "explained").
bool SupportedByHeldOutData(const TorqueErrors& without, const TorqueErrors& with, double explained,
                            double min_explained, double min_gain);

}  // namespace inertial
