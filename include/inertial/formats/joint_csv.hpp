/// @file joint_csv.hpp
/// The project's CSV data contract for joint-space logs, and writers for joint logs and predictions.
///
/// Contract (reading):
/// - The first line is a header of comma-separated column names (surrounding spaces ignored, a
///   UTF-8 byte-order mark tolerated); every later non-blank line is one sample with exactly as many
///   cells. Blank lines are ignored. LF or CRLF line ends. No quoting.
/// - Column `t`: time in seconds, strictly increasing; non-uniform steps are fine. Stamps in other
///   units (milliseconds, nanoseconds: common in ROS exports) are converted with
///   options.time_scale; without it, stamps that do not look like seconds are refused (see
///   ScaleTimeStamps), before anything (differentiation) uses them.
/// - For each actuated joint J: `q_J` (rad or m) and `tau_J` (N m or N) required; `qd_J` and `qdd_J`
///   optional. SI units. Column order is free.
/// - Other columns are ignored (one notice lists them); their cells are not parsed.
/// - Every used cell is a finite decimal number (formats/number_parsing.hpp's ParseDouble).
/// - If qd_J is missing for any joint, all velocities are to be derived from q, for consistency:
///   the reader only reads, so it returns qd as zeros, sets report.missing_qd, and a notice says so
///   (also naming any qd columns thereby ignored); the same, independently, for qdd. Deriving is
///   the preprocessing stage's: DeriveFromPositions (signal/log_differentiation.hpp, a
///   Savitzky-Golay fit of q with options.differentiation), which ReadJointLog below applies.
/// - A row with the same t as the previous accepted row: dropped if its used values are all
///   identical to that row's (counted in a notice); otherwise an error (a bad row).
///
/// Errors (CsvError) name the source, the 1-based line number as an editor shows it, and the column
/// by number and header name, e.g. "log.csv:17: column 3 'q_j1': 'abc' is not a number". Bad rows
/// (a wrong number of cells, a non-numeric or non-finite cell, non-increasing time, a conflicting
/// duplicate) are errors by default; with skip_bad_rows they are skipped and counted, and one notice
/// gives their number, the first few line numbers and the first reason. Missing columns are listed
/// all in one message. An empty file, a header without data rows, or fewer than 2 rows (left after
/// skipping) are errors: one sample has no time step.
#pragma once

#include <Eigen/Core>
#include <istream>
#include <stdexcept>
#include <string>
#include <vector>

#include "inertial/signal/savitzky_golay.hpp"
#include "inertial/model/joint_samples.hpp"

namespace inertial {

struct JointCsvOptions {
  bool skip_bad_rows = false;                  ///< skip and count bad rows instead of rejecting the file
  SavitzkyGolayOptions differentiation;       ///< for qd / qdd derived from q (by ReadJointLog)
  /// Seconds per unit of the t column (1e-3 for milliseconds, 1e-9 for nanoseconds; --time-scale),
  /// or 0: not given, the stamps must look like seconds (ScaleTimeStamps).
  double time_scale = 0.0;
};

struct JointCsvReport {
  std::vector<std::string> notices;  ///< human-readable, one sentence each, prefixed with the source
  int skipped_rows = 0;              ///< bad rows skipped (skip_bad_rows)
  int duplicate_rows = 0;            ///< identical repeated rows dropped
  bool missing_qd = false;           ///< velocities not read: to be derived from q (zeros returned)
  bool missing_qdd = false;          ///< accelerations not read: to be derived from q (zeros returned)
  std::vector<int> lines;            ///< the 1-based file line of each returned sample
};

/// A file that breaks the contract, or cannot be read or written. Message "source:line: ..." style.
/// invalid_value: the file is well formed but a cell is not a finite number (the CLI's exit code 3,
/// as for any value that is not a finite number; other CSV errors are file errors, 5).
struct CsvError : std::runtime_error {
  explicit CsvError(const std::string& message, bool is_invalid_value = false)
      : std::runtime_error(message), invalid_value(is_invalid_value) {}
  bool invalid_value;
};

/// Time stamps that are not seconds. Sampling periods of real logs lie within 1e-5 s (100 kHz) and
/// 1 s (1 Hz), and are rarely whole seconds:
/// - time_scale given (> 0): t is multiplied by it; a median step outside [1e-5, 1] s afterwards is
///   refused (naming --time-scale: a wrong factor).
/// - time_scale 0: t is refused if its median step is below 1e-5 or above 1, or if every stamp is an
///   integer (milliseconds at 1 kHz have a median step of 1; seconds never come as integers). The
///   message says what was seen (the median step) and suggests --time-scale with the factor among
///   1e-3 (ms), 1e-6 (us), 1e-9 (ns) that brings the median step into a plausible sampling period
///   of 1e-4..1e-1 s, when there is one.
/// Fewer than 2 stamps have no step: only scaled. `where` names the file and column in messages,
/// e.g. "log.csv: column 1 't'". Stamps are strictly increasing on entry.
/// Limitation: milliseconds with fractions and a median step below 1 (faster than 1 kHz) look like
/// seconds at a slow rate and pass; only --time-scale can say otherwise.
/// @throws CsvError as above, or if scaling makes a stamp non-finite or two stamps equal;
///   std::invalid_argument if time_scale is negative or not finite.
void ScaleTimeStamps(Eigen::Ref<Eigen::VectorXd> t, double time_scale, const std::string& where);

/// Reads a joint log (contract above) for the joints `joint_names` (their order sets the columns of
/// the result). @throws CsvError as above, also if the file cannot be opened;
/// std::invalid_argument if joint_names is empty or has duplicates, or options.time_scale is
/// negative or not finite.
JointSamples ReadJointCsv(const std::string& path, const std::vector<std::string>& joint_names,
                          const JointCsvOptions& options = {}, JointCsvReport* report = nullptr);

/// A joint log as the offline tools use it: ReadJointCsv, then the preprocessing stage
/// DeriveFromPositions (log_differentiation.hpp) for what the file lacks. @throws as ReadJointCsv,
/// and CsvError "path: cannot derive ..." if the derivation fails.
JointSamples ReadJointLog(const std::string& path, const std::vector<std::string>& joint_names,
                          const JointCsvOptions& options = {}, JointCsvReport* report = nullptr);
/// As ReadJointLog, from a stream; `source_name` stands for the file in messages.
JointSamples ParseJointLog(std::istream& in, const std::string& source_name, const std::vector<std::string>& joint_names,
                           const JointCsvOptions& options = {}, JointCsvReport* report = nullptr);

/// As ReadJointCsv, from a stream; `source_name` stands for the file in messages.
JointSamples ParseJointCsv(std::istream& in, const std::string& source_name, const std::vector<std::string>& joint_names,
                           const JointCsvOptions& options = {}, JointCsvReport* report = nullptr);

/// Writes columns t, q_J..., qd_J..., qdd_J..., tau_J... (joints in samples.joint_names order), every
/// value with %.17g so that reading it back gives the same doubles.
/// @throws std::invalid_argument if the sizes of samples are inconsistent; CsvError if the file
///   cannot be written.
void WriteJointCsv(const std::string& path, const JointSamples& samples);

/// Writes a header row and the rows of `columns` (%.17g), e.g. header t, tau_hat_J... for predictions.
/// @throws std::invalid_argument if header.size() != columns.cols() or a name is empty or contains a
///   comma, quote or line break; CsvError if the file cannot be written.
void WriteColumnsCsv(const std::string& path, const std::vector<std::string>& header, const Eigen::MatrixXd& columns);

}  // namespace inertial
