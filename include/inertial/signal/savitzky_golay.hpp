/// @file savitzky_golay.hpp
/// Savitzky-Golay smoothing and differentiation for non-uniform time stamps: for each sample i, a
/// polynomial of order p in (t - t_i) is fitted by least squares to the samples in a time window
/// around t_i, and its value, first and second derivative at t_i are returned.
///
/// Window: the centred interval [t_i - w/2, t_i + w/2]; near the ends of the data it is shifted to
/// stay inside the data (the nearest full window: [t_0, t_0 + w] or [t_last - w, t_last]); if the
/// data span less than w, the whole data. If that window holds fewer than p + 1 samples, it is
/// widened to the p + 1 samples nearest in time to t_i (so sparse data are still fitted, with a
/// wider support than asked for). Bounds include samples within 1e-9 w of them, so a uniform grid
/// gives symmetric windows despite rounding.
///
/// Conditioning: time is scaled by the largest |t_j - t_i| in the window (the half window w/2 for a
/// centred window) and the fit is solved by QR (modified Gram-Schmidt, reorthogonalized) of the
/// scaled Vandermonde matrix, never by normal equations. All columns of x share one solve per sample.
/// The fit is exact for polynomials of degree <= p. Cost O(N n p (p + m)) for n samples per window
/// and m columns; the work space is allocated once, not per sample.
#pragma once

#include <Eigen/Core>

namespace inertial {

struct SavitzkyGolayOptions {
  int order = 4;        ///< polynomial order p (>= 2, for the second derivative)
  double window = 0.1;  ///< window width w in seconds (> 0)
};

/// Rows are samples, columns are signals (as x).
struct SavitzkyGolayResult {
  Eigen::MatrixXd value;   ///< smoothed x
  Eigen::MatrixXd first;   ///< dx/dt
  Eigen::MatrixXd second;  ///< d^2x/dt^2
};

/// Smooths and differentiates every column of x (rows = samples at times t).
/// @throws std::invalid_argument if t and x have different numbers of rows, order < 2, the window is
///   not positive and finite, t is not finite or not strictly increasing (naming the sample), x is
///   not finite (naming the entry), or there are fewer than order + 1 samples.
SavitzkyGolayResult SavitzkyGolay(const Eigen::VectorXd& t, const Eigen::MatrixXd& x, const SavitzkyGolayOptions& options = {});

}  // namespace inertial
