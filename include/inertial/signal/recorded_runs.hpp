/// @file recorded_runs.hpp
/// Several recorded runs of one robot, fitted as one model: each run is read and differentiated on
/// its own (log_differentiation.hpp: no seams), then the runs are laid end to end in one log, so
/// that a fit stacks their torque equations. Later runs are shifted in time to start a clear gap
/// after the previous one ends (kRunSeparation), so that nothing downstream that looks at time
/// (the held-out split, where-it-fails windows, the noise's autocorrelation) reads across a seam;
/// the shifts are kept to name times in each run's own clock.
#pragma once

#include <string>
#include <vector>

#include "inertial/model/joint_samples.hpp"

namespace inertial {

/// Seconds between the end of one run and the start of the next once laid end to end, at least:
/// longer than the 1 s windows of where-it-fails (model_comparison.hpp) and, with 10 median steps
/// of the previous run when those are longer, a gap to log_differentiation.hpp's rule as well.
inline constexpr double kRunSeparation = 1.0;

struct RecordedRuns {
  std::vector<std::string> names;  ///< each run's source (its file)
  std::vector<int> starts;         ///< the first row of each run in `samples`, then samples.size()
  std::vector<double> shifts;      ///< added to each run's own time stamps in `samples`
  JointSamples samples;            ///< every run's rows, run after run

  int num_runs() const { return static_cast<int>(names.size()); }
  /// Run k's rows (times as laid end to end: subtract shifts[k] for its own clock).
  JointSamples Run(int k) const;
};

/// Lays `runs` end to end (same joints, in order). @throws std::invalid_argument if there is no run,
/// names and runs differ in number, a run is empty, or the runs' joints differ (naming the run).
RecordedRuns JoinRuns(const std::vector<std::string>& names, const std::vector<JointSamples>& runs);

/// The last `fraction` of each run's duration held out (HoldoutStart, sample_selection.hpp), the
/// rest of each for training; both keep the runs' names and shifts.
/// @throws std::invalid_argument as HoldoutStart, naming the run.
void SplitRunsHoldout(const RecordedRuns& runs, double fraction, RecordedRuns* train, RecordedRuns* validation);

}  // namespace inertial
