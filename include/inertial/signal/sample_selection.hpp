/// @file sample_selection.hpp
/// Choosing rows of a joint log: the rows kept when some are left out (glitches, outliers, a
/// held-out part), and the log of those rows. Conventions: rows are samples in time order
/// (joint_samples.hpp); indices are 0-based.
#pragma once

#include <vector>

#include "inertial/model/joint_samples.hpp"

namespace inertial {

/// The samples `keep_rows` of data (in that order; ascending keeps t increasing), joint names copied.
/// @throws std::invalid_argument if an index is outside [0, data.size()) or data's arrays do not all
///   have data.size() rows.
JointSamples SelectSamples(const JointSamples& data, const std::vector<int>& keep_rows);

/// The rows 0..n-1 that are not in `sorted_rows` (ascending, each in [0, n)), ascending: the rows to
/// keep when `sorted_rows` are left out.
std::vector<int> RowsExcept(int n, const std::vector<int>& sorted_rows);

/// The first row of the held-out part of a log: the last `fraction` of its duration, by its time
/// stamps (a jittered or paused log splits where its time says, not where its sample count does).
/// @throws std::invalid_argument unless 0 < fraction < 1 and both parts keep at least 2 samples.
int HoldoutStart(const Eigen::VectorXd& t, double fraction);

/// The rows begin, begin + stride, ... below end (stride >= 1).
std::vector<int> RowRange(int begin, int end, int stride = 1);

}  // namespace inertial
