/// @file sample_glitches.hpp
/// Glitched samples of smoothly sampled signals, found without a model: a bus error, a flipped
/// digit, a sensor's saturation code in one sample. Batch fits need this where a glitch sits in a
/// regressor (a single body's twist): such a row has high leverage, drags the least-squares fit to
/// itself, and then leaves a small residual, so residual-based rejection (robust_identification.hpp)
/// cannot see it; one vx of 1000 among 4000 samples of 0.03 rad/s turned a 0.7 kg body into
/// 2e-5 kg with its centre of mass 87 m away, and the fit took 50 times as long.
///
/// Method (FindGlitches), for each column x of a signal matrix (rows = samples in time order):
///   expected e_i  interior rows: the median of x_{i-2}, x_{i-1}, x_{i+1}, x_{i+2} (one glitched
///                 neighbour cannot move it; for a smooth signal it differs from x_i by
///                 O(h^2 x'')); the two first and last rows: the median of the linear
///                 extrapolations to i through each pair of the 5 nearest rows on the inside (10
///                 pairs, of which one glitched row spoils 4).
///   deviation     d_i = x_i - e_i; its robust scale s = 1.4826 MAD(d) over the column, floored at
///                 1e-3 of the column's RMS (the resolution of real sensing, as in
///                 robust_identification.hpp: noise-free data would otherwise have s ~ 1e-12) and at
///                 1e-9 (a column that is identically zero).
///   glitch        |d_i| > k s, with k = DefaultOutlierThreshold(rows x columns) (Laplace tails:
///                 0.01 good values wrongly flagged per log, 14.5 for 4000 x 12), and also
///                 |d_i| > 2 r_i, where r_i is the spread (max - min) of the neighbours above less
///                 the one furthest from their median: the value leaves its neighbourhood by twice
///                 the neighbourhood's own extent. That second test keeps steps (an impact, the
///                 start of a motion in a log that is mostly at rest, where s is tiny) and fast but
///                 continuous motion: there the neighbours spread as far as the value departs.
/// Rows are samples; the neighbours are not weighted by time, so at a gap in time a value is judged
/// as if the samples were evenly spaced; the spread test keeps it unless it leaves neighbours that
/// agree with one another, which a signal that merely moved during the gap does not do.
/// Cost: O(rows x columns) plus two medians per column.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "inertial/model/body_effect_model.hpp"

namespace inertial {

struct SampleGlitch {
  int row = 0;
  int column = 0;          ///< the column furthest out in this row
  double value = 0.0;
  double expected = 0.0;   ///< e_i above
  double scales = 0.0;     ///< |value - expected| / s
};

struct GlitchScreen {
  std::vector<SampleGlitch> glitches;  ///< one per glitched row, ascending rows
  double threshold = 0.0;              ///< the k used
  std::vector<int> Rows() const;       ///< the glitched rows, ascending
};

/// The glitched rows of `signals` (method above). Fewer than 7 rows: none (too few neighbours to
/// judge). threshold: k, or 0 for the default above.
/// @throws std::invalid_argument if a value is not finite or threshold is negative or not finite.
GlitchScreen FindGlitches(const Eigen::MatrixXd& signals, double threshold = 0.0);

/// A single-body log's signals, one column each: wx wy wz vx vy vz mx my mz fx fy fz, then
/// gx gy gz when the log has gravity (names as the body CSV's columns).
Eigen::MatrixXd BodySignals(const BodyLog& log);
std::vector<std::string> BodySignalNames(const BodyLog& log);

/// The samples `keep_rows` of log (ascending), gravity with them.
/// @throws std::invalid_argument if an index is outside the log.
BodyLog SelectBodySamples(const BodyLog& log, const std::vector<int>& keep_rows);

/// "sample 2000 (t = 20 s): vx = 1000, expected 0.0311 from its neighbours (2.3e+06 robust scales)".
std::string DescribeGlitch(const BodyLog& log, const SampleGlitch& glitch);

}  // namespace inertial
