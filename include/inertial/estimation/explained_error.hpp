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

namespace inertial {

/// @throws std::invalid_argument if the sizes differ or are zero.
double ExplainedShare(const Eigen::VectorXd& rms_without, const Eigen::VectorXd& rms_with);

}  // namespace inertial
