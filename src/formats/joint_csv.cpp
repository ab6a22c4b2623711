#include "inertial/formats/joint_csv.hpp"
#include "inertial/signal/robust_statistics.hpp"

#include "inertial/signal/log_differentiation.hpp"
#include "inertial/signal/sample_selection.hpp"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <memory>
#include <string_view>
#include <tuple>
#include <unordered_map>

#include "csv_text.hpp"
#include "inertial/formats/file_error.hpp"
#include "inertial/formats/number_parsing.hpp"
#include "inertial/model/number_text.hpp"

namespace inertial {
namespace {

using csv::IsBlank;
using csv::LineReader;
using csv::ReadAll;
using csv::SplitCells;
using csv::Trim;

constexpr int kListedBadLines = 5;  // line numbers named in the skipped-rows notice

std::string Join(const std::vector<std::string>& items) {
  std::string out;
  for (std::size_t k = 0; k < items.size(); ++k) out += (k ? ", " : "") + items[k];
  return out;
}

// Time stamps (ScaleTimeStamps): sampling periods of real logs, and the plausible range a suggested
// factor must bring the median step into.
constexpr double kSmallestStep = 1e-5;      // s: 100 kHz
constexpr double kLargestStep = 1.0;        // s: 1 Hz
constexpr double kPlausibleSmallest = 1e-4;  // s: 10 kHz
constexpr double kPlausibleLargest = 1e-1;   // s: 10 Hz

/// "if they are milliseconds, give --time-scale 1e-3 (a median step of 0.001 s)", or a general hint.
std::string TimeScaleSuggestion(double median_step) {
  const std::pair<double, const char*> units[] = {{1e-3, "milliseconds"}, {1e-6, "microseconds"}, {1e-9, "nanoseconds"}};
  const char* const texts[] = {"1e-3", "1e-6", "1e-9"};
  for (int u = 0; u < 3; ++u) {
    const double step = units[u].first * median_step;
    if (step >= kPlausibleSmallest && step <= kPlausibleLargest) {
      return std::string("if they are ") + units[u].second + ", give --time-scale " + texts[u] + " (a median step of " +
             FormatNumber(step, 4) + " s)";
    }
  }
  return "give --time-scale with the factor that converts them to seconds (1e-3 for ms, 1e-6 for us, 1e-9 for ns)";
}

/// What a used column feeds: the time or one joint's q, qd, qdd or tau.
enum class Kind { kTime, kQ, kQd, kQdd, kTau };

struct UsedColumn {
  int column = 0;  // 0-based in the header
  Kind kind = Kind::kTime;
  int joint = 0;
};

class Parser {
 public:
  Parser(const std::string& source, const std::vector<std::string>& joints, const JointCsvOptions& options, JointCsvReport& report)
      : source_(source), joints_(joints), options_(options), report_(report) {}

  JointSamples Parse(std::string_view text) {
    LineReader lines(text);
    std::string_view line;
    if (IsBlank(text)) throw CsvError(source_ + ": empty file (expected a header row with columns t, q_J, tau_J)");
    lines.Next(line);
    if (line.size() >= 3 && line.substr(0, 3) == "\xEF\xBB\xBF") line.remove_prefix(3);  // UTF-8 BOM
    if (IsBlank(line)) throw CsvError(source_ + ":1: empty header row (expected column names t, q_J, tau_J)");
    ReadHeader(line);

    std::vector<std::string_view> cells;
    std::vector<double> row(used_.size());
    values_.reserve(static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n') + 1) * used_.size());
    int data_lines = 0;
    while (lines.Next(line)) {
      if (IsBlank(line)) continue;
      ++data_lines;
      const int number = lines.number();
      SplitCells(line, cells);
      if (cells.size() != header_.size()) {
        Bad(number, source_ + ":" + std::to_string(number) + ": " + std::to_string(cells.size()) + " cells, but the header has " +
                        std::to_string(header_.size()) + " columns");
        continue;
      }
      if (!ParseRow(number, cells, row)) continue;
      if (!CheckTime(number, row)) continue;
      values_.insert(values_.end(), row.begin(), row.end());
      report_.lines.push_back(number);
      previous_line_ = number;
    }
    if (data_lines == 0) throw CsvError(source_ + ": no data rows after the header (line 1)");
    const int rows = static_cast<int>(values_.size() / used_.size());
    if (rows == 0) {
      throw CsvError(source_ + ": no data rows left after skipping " + std::to_string(report_.skipped_rows) + " bad rows (first: " +
                     first_reason_ + ")");
    }
    if (rows == 1) {  // no time step: nothing downstream (differentiation, a fit, an estimator's rates) can use it
      throw CsvError(source_ + ": only 1 data row" +
                     (report_.skipped_rows > 0 ? " left after skipping " + std::to_string(report_.skipped_rows) +
                                                     " bad rows (first: " + first_reason_ + ")"
                                               : std::string()) +
                     "; a log needs at least 2 samples");
    }
    return Assemble(rows);
  }

 private:
  std::string Column(int column) const {
    return "column " + std::to_string(column + 1) + " '" + header_[static_cast<std::size_t>(column)] + "'";
  }

  void ReadHeader(std::string_view line) {
    std::vector<std::string_view> cells;
    SplitCells(line, cells);
    std::unordered_map<std::string, int> index;
    for (std::size_t c = 0; c < cells.size(); ++c) {
      header_.emplace_back(cells[c]);
      if (header_.back().empty()) continue;
      const auto [it, inserted] = index.emplace(header_.back(), static_cast<int>(c));
      if (!inserted) {
        throw CsvError(source_ + ":1: " + Column(static_cast<int>(c)) + " repeats column " + std::to_string(it->second + 1) +
                       " (column names must be unique)");
      }
    }
    std::vector<std::string> missing, missing_qd, missing_qdd;
    std::vector<bool> used(header_.size(), false);
    auto find = [&](const std::string& name) {
      const auto it = index.find(name);
      return it == index.end() ? -1 : it->second;
    };
    if (find("t") < 0) missing.push_back("t");
    for (const std::string& j : joints_) {
      for (const char* prefix : {"q_", "tau_"}) {
        if (find(prefix + j) < 0) missing.push_back(prefix + j);
      }
      if (find("qd_" + j) < 0) missing_qd.push_back("qd_" + j);
      if (find("qdd_" + j) < 0) missing_qdd.push_back("qdd_" + j);
    }
    if (!missing.empty()) {
      throw CsvError(source_ + ":1: missing column" + (missing.size() > 1 ? "s " : " ") + Join(missing) +
                     " (the header has: " + Join(header_) + ")");
    }
    derive_qd_ = !missing_qd.empty();
    derive_qdd_ = !missing_qdd.empty();

    auto use = [&](const std::string& name, Kind kind, int joint) {
      const int column = find(name);
      used_.push_back({column, kind, joint});
      used[static_cast<std::size_t>(column)] = true;
    };
    use("t", Kind::kTime, 0);
    std::vector<std::string> ignored_qd, ignored_qdd;
    for (int j = 0; j < static_cast<int>(joints_.size()); ++j) {
      const std::string& name = joints_[static_cast<std::size_t>(j)];
      use("q_" + name, Kind::kQ, j);
      use("tau_" + name, Kind::kTau, j);
      // A kind being derived ignores its given columns (named in the derivation notice, not as extra).
      for (const auto& [prefix, kind, derive, ignored] :
           {std::tuple<const char*, Kind, bool, std::vector<std::string>*>{"qd_", Kind::kQd, derive_qd_, &ignored_qd},
            {"qdd_", Kind::kQdd, derive_qdd_, &ignored_qdd}}) {
        const std::string column = prefix + name;
        if (!derive) {
          use(column, kind, j);
        } else if (find(column) >= 0) {
          ignored->push_back(column);
          used[static_cast<std::size_t>(find(column))] = true;
        }
      }
    }
    std::sort(used_.begin(), used_.end(), [](const UsedColumn& a, const UsedColumn& b) { return a.column < b.column; });
    for (std::size_t s = 0; s < used_.size(); ++s) {
      if (used_[s].kind == Kind::kTime) time_slot_ = static_cast<int>(s);
    }

    std::vector<std::string> extra;
    for (std::size_t c = 0; c < header_.size(); ++c) {
      if (!used[c]) extra.push_back(header_[c].empty() ? "(unnamed column " + std::to_string(c + 1) + ")" : header_[c]);
    }
    if (!extra.empty()) {
      report_.notices.push_back(source_ + ": ignored " + std::to_string(extra.size()) + " extra column" +
                                (extra.size() > 1 ? "s: " : ": ") + Join(extra));
    }
    // What is missing is the derivation stage's (log_differentiation.hpp), which says how it derives.
    if (derive_qd_) {
      report_.notices.push_back(source_ + ": no velocity column " + Join(missing_qd) +
                                (ignored_qd.empty() ? "" : " (so " + Join(ignored_qd) + " is ignored too: all velocities come from q)"));
    }
    if (derive_qdd_) {
      report_.notices.push_back(source_ + ": no acceleration column " + Join(missing_qdd) +
                                (ignored_qdd.empty() ? "" : " (so " + Join(ignored_qdd) + " is ignored too: all accelerations come from q)"));
    }
  }

  /// Parses the used cells into row; false (after Bad) if one is not a finite number.
  bool ParseRow(int number, const std::vector<std::string_view>& cells, std::vector<double>& row) {
    for (std::size_t s = 0; s < used_.size(); ++s) {
      const std::string_view cell = cells[static_cast<std::size_t>(used_[s].column)];
      double value = 0.0;
      const std::from_chars_result r = std::from_chars(cell.data(), cell.data() + cell.size(), value);
      if (r.ec != std::errc() || r.ptr != cell.data() + cell.size() || cell.empty() || !std::isfinite(value)) {
        // Not the plain case: ParseDouble decides (it accepts a leading '+') and words the error.
        try {
          value = ParseDouble(cell, source_ + ":" + std::to_string(number) + ": " + Column(used_[s].column));
        } catch (const InvalidNumber& e) {
          Bad(number, e.what(), /*invalid_value=*/true);
          return false;
        }
      }
      row[s] = value;
    }
    return true;
  }

  /// Checks t against the previous accepted row; false if the row is to be dropped (duplicate) or
  /// is bad (after Bad).
  bool CheckTime(int number, const std::vector<double>& row) {
    if (values_.empty()) return true;
    const double* previous = values_.data() + values_.size() - row.size();
    const double t = row[static_cast<std::size_t>(time_slot_)];
    const double t_previous = previous[time_slot_];
    const std::string where = source_ + ":" + std::to_string(number) + ": ";
    if (t == t_previous) {
      for (std::size_t s = 0; s < row.size(); ++s) {
        if (row[s] != previous[s]) {
          Bad(number, where + "same time " + FormatNumberExact(t) + " as line " + std::to_string(previous_line_) +
                          " but different values (" + Column(used_[s].column) + ": " + FormatNumberExact(row[s]) + " vs " +
                          FormatNumberExact(previous[s]) + ")");
          return false;
        }
      }
      if (report_.duplicate_rows++ == 0) first_duplicate_line_ = number;
      return false;
    }
    if (t < t_previous) {
      Bad(number, where + Column(used_[static_cast<std::size_t>(time_slot_)].column) + ": time " + FormatNumberExact(t) +
                      " is not after the previous row's " + FormatNumberExact(t_previous) + " (line " + std::to_string(previous_line_) +
                      "); t must be strictly increasing");
      return false;
    }
    return true;
  }

  void Bad(int number, const std::string& message, bool invalid_value = false) {
    if (!options_.skip_bad_rows) throw CsvError(message, invalid_value);
    if (report_.skipped_rows == 0) first_reason_ = message;
    if (report_.skipped_rows < kListedBadLines) bad_lines_.push_back(std::to_string(number));
    ++report_.skipped_rows;
  }

  JointSamples Assemble(int rows) {
    const int n = static_cast<int>(joints_.size());
    JointSamples samples;
    samples.joint_names = joints_;
    samples.t.resize(rows);
    samples.q.resize(rows, n);
    samples.qd.resize(rows, n);
    samples.qdd.resize(rows, n);
    samples.tau.resize(rows, n);
    const std::size_t width = used_.size();
    for (std::size_t s = 0; s < width; ++s) {
      const UsedColumn& u = used_[s];
      double* column = nullptr;
      switch (u.kind) {
        case Kind::kTime: column = samples.t.data(); break;
        case Kind::kQ: column = samples.q.col(u.joint).data(); break;
        case Kind::kQd: column = samples.qd.col(u.joint).data(); break;
        case Kind::kQdd: column = samples.qdd.col(u.joint).data(); break;
        case Kind::kTau: column = samples.tau.col(u.joint).data(); break;
      }
      for (int r = 0; r < rows; ++r) column[r] = values_[static_cast<std::size_t>(r) * width + s];
    }
    if (report_.duplicate_rows > 0) {
      report_.notices.push_back(source_ + ": dropped " + std::to_string(report_.duplicate_rows) +
                                " duplicated row(s) (same time and values as the previous row), the first at line " +
                                std::to_string(first_duplicate_line_));
    }
    if (report_.skipped_rows > 0) {
      report_.notices.push_back(source_ + ": skipped " + std::to_string(report_.skipped_rows) + " bad row(s) at line" +
                                (report_.skipped_rows > 1 ? "s " : " ") + Join(bad_lines_) +
                                (report_.skipped_rows > kListedBadLines ? ", ..." : "") + "; the first: " + first_reason_);
    }
    ScaleTimeStamps(samples.t, options_.time_scale, source_ + ": " + Column(used_[static_cast<std::size_t>(time_slot_)].column));
    // Derivatives of q are the preprocessing stage's (signal/log_differentiation.hpp): the
    // missing columns are zero here and the report says which.
    if (derive_qd_) samples.qd.setZero();
    if (derive_qdd_) samples.qdd.setZero();
    report_.missing_qd = derive_qd_;
    report_.missing_qdd = derive_qdd_;
    return samples;
  }

  const std::string& source_;
  const std::vector<std::string>& joints_;
  const JointCsvOptions& options_;
  JointCsvReport& report_;

  std::vector<std::string> header_;
  std::vector<UsedColumn> used_;  // in header order
  int time_slot_ = 0;
  bool derive_qd_ = false;
  bool derive_qdd_ = false;

  std::vector<double> values_;  // accepted rows, row-major, used_.size() per row
  int previous_line_ = 0;
  int first_duplicate_line_ = 0;
  std::vector<std::string> bad_lines_;
  std::string first_reason_;
};

void CheckJointNames(const std::vector<std::string>& joint_names) {
  if (joint_names.empty()) throw std::invalid_argument("joint CSV: no joint names given");
  for (std::size_t a = 0; a < joint_names.size(); ++a) {
    if (joint_names[a].empty()) throw std::invalid_argument("joint CSV: joint name " + std::to_string(a + 1) + " is empty");
    for (std::size_t b = 0; b < a; ++b) {
      if (joint_names[a] == joint_names[b]) throw std::invalid_argument("joint CSV: joint name '" + joint_names[a] + "' is given twice");
    }
  }
}

void CheckColumnName(const std::string& name, const std::string& what) {
  if (name.empty() || name.find_first_of(",\"\r\n") != std::string::npos) {
    throw std::invalid_argument(what + " '" + name + "' cannot be a CSV column name (empty, or has a comma, quote or line break)");
  }
}

/// Buffered writing of a CSV file with a C FILE, reporting failures by path.
class CsvFileWriter {
 public:
  explicit CsvFileWriter(const std::string& path) : path_(path), file_(std::fopen(path.c_str(), "wb"), &std::fclose) {
    if (!file_) throw CsvError(CannotText("write", "", path));
    buffer_.reserve(kFlushSize + 4096);
  }
  void Header(const std::vector<std::string>& names) {
    for (std::size_t k = 0; k < names.size(); ++k) buffer_ += (k ? "," : "") + names[k];
    buffer_ += '\n';
  }
  void Cell(double value, bool first) {
    if (!first) buffer_ += ',';
    buffer_ += FormatNumber(value, kRoundTripDigits);
  }
  void EndRow() {
    buffer_ += '\n';
    if (buffer_.size() >= kFlushSize) Flush();
  }
  void Close() {
    Flush();
    std::FILE* file = file_.release();
    if (std::fclose(file) != 0) throw CsvError("cannot finish writing '" + path_ + "': " + std::strerror(errno));
  }

 private:
  static constexpr std::size_t kFlushSize = 1 << 20;
  void Flush() {
    if (!buffer_.empty() && std::fwrite(buffer_.data(), 1, buffer_.size(), file_.get()) != buffer_.size()) {
      throw CsvError(CannotText("write", "", path_));
    }
    buffer_.clear();
  }
  std::string path_;
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> file_;
  std::string buffer_;
};

}  // namespace

void ScaleTimeStamps(Eigen::Ref<Eigen::VectorXd> t, double time_scale, const std::string& where) {
  if (!(time_scale >= 0.0) || !std::isfinite(time_scale)) {
    throw std::invalid_argument("time scale (--time-scale) must be a positive finite number, or 0 for seconds; got " +
                                FormatNumberExact(time_scale));
  }
  const bool given = time_scale > 0.0;
  if (given) {
    t *= time_scale;
    for (Eigen::Index i = 0; i < t.size(); ++i) {
      if (!std::isfinite(t[i]) || (i > 0 && !(t[i] > t[i - 1]))) {
        throw CsvError(where + ": stamp " + std::to_string(i + 1) + " times --time-scale " + FormatNumberExact(time_scale) + " is " +
                       FormatNumberExact(t[i]) + (std::isfinite(t[i]) ? ", not after the previous one" : ", not finite"));
      }
    }
  }
  if (t.size() < 2) return;  // no step to judge
  const double step = MedianStep(t);
  if (given) {
    if (step < kSmallestStep || step > kLargestStep) {
      throw CsvError(where + ": median time step " + FormatNumber(step, 4) + " s after --time-scale " + FormatNumberExact(time_scale) +
                     ", outside the sampling periods of real logs (1e-05 to 1 s); check --time-scale (1e-3 for ms, "
                     "1e-6 for us, 1e-9 for ns)");
    }
    return;
  }
  const bool integers = (t.array() == t.array().floor()).all();
  if (step >= kSmallestStep && step <= kLargestStep && !integers) return;
  std::string seen = "median step " + FormatNumber(step, 4);
  if (step < kSmallestStep) seen += " (as seconds, faster than 100 kHz)";
  if (step > kLargestStep) seen += " (as seconds, slower than 1 Hz)";
  if (integers) seen += ", every stamp an integer";
  throw CsvError(where + ": the time stamps do not look like seconds: " + seen + "; " +
                 (step < kSmallestStep ? std::string("give --time-scale with the factor that converts them to seconds")
                                       : TimeScaleSuggestion(step)) +
                 (integers && step >= kSmallestStep && step <= kLargestStep
                      ? " (if they are whole seconds, --time-scale 1 accepts them)"
                      : ""));
}

JointSamples ParseJointCsv(std::istream& in, const std::string& source_name, const std::vector<std::string>& joint_names,
                           const JointCsvOptions& options, JointCsvReport* report) {
  CheckJointNames(joint_names);
  if (!(options.time_scale >= 0.0) || !std::isfinite(options.time_scale)) {
    throw std::invalid_argument("joint CSV: the time scale (--time-scale) must be a positive finite number, or 0 for "
                                "seconds; got " + FormatNumberExact(options.time_scale));
  }
  const std::string text = ReadAll(in, source_name);
  JointCsvReport local;
  if (report) *report = JointCsvReport{};
  Parser parser(source_name, joint_names, options, report ? *report : local);
  return parser.Parse(text);
}

JointSamples ReadJointCsv(const std::string& path, const std::vector<std::string>& joint_names, const JointCsvOptions& options,
                          JointCsvReport* report) {
  CheckJointNames(joint_names);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw CsvError(CannotText("read", "", path));
  return ParseJointCsv(in, path, joint_names, options, report);
}

JointSamples ParseJointLog(std::istream& in, const std::string& source_name, const std::vector<std::string>& joint_names,
                           const JointCsvOptions& options, JointCsvReport* report) {
  JointCsvReport local;
  JointCsvReport& r = report ? *report : local;
  JointSamples log = ParseJointCsv(in, source_name, joint_names, options, &r);
  LogDerivation derivation;
  try {
    derivation = DeriveFromPositions(&log, r.missing_qd, r.missing_qdd, options.differentiation);
  } catch (const std::invalid_argument& e) {
    throw CsvError(source_name + ": " + e.what());
  }
  for (const std::string& n : derivation.notices) r.notices.push_back(source_name + ": " + n);
  if (!derivation.left_out.empty()) {  // the file lines of the samples kept
    std::vector<int> lines;
    for (int i : RowsExcept(static_cast<int>(r.lines.size()), derivation.left_out)) lines.push_back(r.lines[static_cast<size_t>(i)]);
    r.lines = std::move(lines);
  }
  return log;
}

JointSamples ReadJointLog(const std::string& path, const std::vector<std::string>& joint_names, const JointCsvOptions& options,
                          JointCsvReport* report) {
  CheckJointNames(joint_names);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw CsvError(CannotText("read", "", path));
  return ParseJointLog(in, path, joint_names, options, report);
}

void WriteJointCsv(const std::string& path, const JointSamples& samples) {
  const Eigen::Index rows = samples.t.size();
  const Eigen::Index n = static_cast<Eigen::Index>(samples.joint_names.size());
  CheckJointNames(samples.joint_names);
  for (const auto& [name, m] : {std::pair<const char*, const Eigen::MatrixXd*>{"q", &samples.q}, {"qd", &samples.qd},
                                {"qdd", &samples.qdd}, {"tau", &samples.tau}}) {
    if (m->rows() != rows || m->cols() != n) {
      throw std::invalid_argument("WriteJointCsv: " + std::string(name) + " is " + std::to_string(m->rows()) + " x " +
                                  std::to_string(m->cols()) + ", expected " + std::to_string(rows) + " x " + std::to_string(n) +
                                  " (samples x joints)");
    }
  }
  std::vector<std::string> header{"t"};
  for (const char* prefix : {"q_", "qd_", "qdd_", "tau_"}) {
    for (const std::string& j : samples.joint_names) {
      CheckColumnName(j, "joint name");
      header.push_back(prefix + j);
    }
  }
  CsvFileWriter writer(path);
  writer.Header(header);
  for (Eigen::Index r = 0; r < rows; ++r) {
    writer.Cell(samples.t[r], true);
    for (const Eigen::MatrixXd* m : {&samples.q, &samples.qd, &samples.qdd, &samples.tau}) {
      for (Eigen::Index j = 0; j < n; ++j) writer.Cell((*m)(r, j), false);
    }
    writer.EndRow();
  }
  writer.Close();
}

void WriteColumnsCsv(const std::string& path, const std::vector<std::string>& header, const Eigen::MatrixXd& columns) {
  if (static_cast<Eigen::Index>(header.size()) != columns.cols()) {
    throw std::invalid_argument("WriteColumnsCsv: " + std::to_string(header.size()) + " column names for " +
                                std::to_string(columns.cols()) + " columns");
  }
  for (const std::string& name : header) CheckColumnName(name, "column name");
  CsvFileWriter writer(path);
  writer.Header(header);
  for (Eigen::Index r = 0; r < columns.rows(); ++r) {
    for (Eigen::Index c = 0; c < columns.cols(); ++c) writer.Cell(columns(r, c), c == 0);
    writer.EndRow();
  }
  writer.Close();
}

}  // namespace inertial
