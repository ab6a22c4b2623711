/// @file log_differentiation.hpp
/// The preprocessing stage of a recorded log (a whole joint log at once): the velocities and
/// accelerations its source did not measure, from its positions by Savitzky-Golay
/// (savitzky_golay.hpp, on the log's own time stamps, jitter and all). Non-causal, so better than
/// the stream's causal filter (stream_preprocessor.hpp), and only for logs. Readers
/// (formats/joint_csv.hpp) only read and say what is missing; this derives it and says how.
///
/// Gaps: a controller that pauses its logging (a dropped connection, a paused recorder) leaves a
/// step much longer than the others; a polynomial fitted across it would invent the motion in
/// between. The log is cut at every gap (GapLimit: a step longer than kGapMedianSteps median steps
/// and than half the Savitzky-Golay window), and each piece is differentiated on its own; a piece
/// too short for the polynomial is left out. A shorter hole (a few samples lost by a 1 kHz logger)
/// is bridged: no derivative is asked inside it, and every sample beside it keeps samples of both
/// sides in its centred window, so its fit interpolates. Cutting there instead made the samples at
/// each cut the end of a piece, whose derivatives come from a one-sided window (Savitzky-Golay's
/// second derivative at a window's end has tens of times the noise of its centre's): on a real
/// 1 kHz arm two holes of 8 samples per log raised identify's held-out error by 10 %.
#pragma once

#include <string>
#include <vector>

#include "inertial/signal/savitzky_golay.hpp"
#include "inertial/model/joint_samples.hpp"

namespace inertial {

/// A step longer than this many median steps (and than half the window, GapLimit) is a gap.
/// Controller logs jitter: the steps of a 100 Hz arm seen in the field lie within 0.2 and 3.4 median
/// steps, and a gap counter of the stream (signal/stream_gap_counter.hpp) already calls 1.5 median
/// steps a lost sample; cutting there would cut at every late sample. At 5 median steps at least 4
/// samples in a row are missing: at 100 Hz that is half the 0.1 s window, where a polynomial about a
/// sample beside the hole would rest on one side's samples and extrapolate across it.
inline constexpr double kGapMedianSteps = 5.0;

/// The longest step that is not a gap: max(kGapMedianSteps * median step, window / 2). Beyond half
/// the window, the centred window of a sample beside the hole holds no sample of its other side
/// (the fit is one-sided whatever is done), and a cut at least lets the window shift to a full
/// window of the near side; below it, bridging keeps both sides (file comment).
double GapLimit(const Eigen::VectorXd& t, const SavitzkyGolayOptions& options);

/// What the stage did, for the user.
struct LogDerivation {
  /// What was derived and how, the gaps cut at and the rows left out: sentences, without the
  /// log's name (the caller prefixes it).
  std::vector<std::string> notices;
  std::vector<int> piece_starts{0};  ///< the first row of each piece differentiated on its own
  std::vector<int> left_out;         ///< rows (ascending) of pieces too short to differentiate, removed
};

/// The rows that start a new piece after a gap (a step above GapLimit; ascending, never 0); none if
/// t has fewer than 3 steps.
std::vector<int> GapStarts(const Eigen::VectorXd& t, const SavitzkyGolayOptions& options);

/// Replaces log->qd (if `velocities`) and log->qdd (if `accelerations`) by the first and second
/// derivative of one Savitzky-Golay fit of log->q per piece between gaps; nothing if neither is
/// asked for. Pieces with fewer than order + 1 samples are removed from *log (named in a notice).
/// @throws std::invalid_argument saying why: the fit cannot be made (savitzky_golay.hpp: too few
///   samples for the order in every piece, a bad window), or a derivative is not finite (finite
///   positions can still overflow over very short steps), naming the sample and its time.
LogDerivation DeriveFromPositions(JointSamples* log, bool velocities, bool accelerations, const SavitzkyGolayOptions& options);

}  // namespace inertial
