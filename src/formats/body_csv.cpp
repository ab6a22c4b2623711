#include "inertial/formats/body_csv.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <unordered_map>

#include "csv_text.hpp"
#include "inertial/formats/file_error.hpp"
#include "inertial/formats/number_parsing.hpp"

namespace inertial {
namespace {

constexpr const char* kColumns[] = {"t", "wx", "wy", "wz", "vx", "vy", "vz", "mx", "my", "mz", "fx", "fy", "fz"};
constexpr const char* kGravity[] = {"gx", "gy", "gz"};

// The header row's columns: their names, and the indices of those read (kColumns' in order, then
// the gravity columns when present).
struct BodyColumns {
  std::vector<std::string> header;
  std::vector<int> used;
  int gravity_columns = 0;
};

// Reads the header row (line 1, byte-order mark removed): rejects repeated, missing or partial gravity
// columns, and notes the columns ignored.
BodyColumns ReadBodyHeader(std::string_view line, const std::string& source, std::vector<std::string>* notices) {
  BodyColumns columns;
  std::vector<std::string_view> cells;
  csv::SplitCells(line, cells);
  std::vector<std::string>& header = columns.header;
  header.assign(cells.begin(), cells.end());
  std::unordered_map<std::string, int> index;
  for (int c = 0; c < static_cast<int>(header.size()); ++c) {
    if (!header[c].empty() && !index.emplace(header[c], c).second) {
      throw CsvError(source + ":1: column " + std::to_string(c + 1) + " '" + header[c] + "' is repeated");
    }
  }
  std::vector<int>& used = columns.used;
  std::string missing;
  for (const char* name : kColumns) {
    const auto it = index.find(name);
    if (it == index.end()) {
      missing += (missing.empty() ? "" : ", ") + std::string(name);
    } else {
      used.push_back(it->second);
    }
  }
  if (!missing.empty()) throw CsvError(source + ":1: missing columns " + missing);
  int& gravity_columns = columns.gravity_columns;
  for (const char* name : kGravity) {
    const auto it = index.find(name);
    if (it != index.end()) {
      used.push_back(it->second);
      ++gravity_columns;
    }
  }
  if (gravity_columns != 0 && gravity_columns != 3) {
    throw CsvError(source + ":1: gravity needs all of gx, gy, gz (or none)");
  }
  if (notices != nullptr && header.size() > used.size()) {
    std::string extra;
    for (int c = 0; c < static_cast<int>(header.size()); ++c) {
      if (std::find(used.begin(), used.end(), c) == used.end()) extra += (extra.empty() ? "" : ", ") + header[c];
    }
    notices->push_back(source + ": columns ignored: " + extra);
  }
  return columns;
}

}  // namespace

BodyLog ParseBodyCsv(std::istream& in, const std::string& source, std::vector<std::string>* notices, double time_scale) {
  if (!(time_scale >= 0.0) || !std::isfinite(time_scale)) {
    throw std::invalid_argument("body CSV: the time scale (--time-scale) must be a positive finite number, or 0 for seconds");
  }
  const std::string text = csv::ReadAll(in, source);
  csv::LineReader lines(text);
  std::string_view line;
  if (csv::IsBlank(text)) throw CsvError(source + ": empty file (expected a header row t, wx, ..., fz)");
  lines.Next(line);
  if (line.size() >= 3 && line.substr(0, 3) == "\xEF\xBB\xBF") line.remove_prefix(3);
  const BodyColumns columns = ReadBodyHeader(line, source, notices);
  const std::vector<std::string>& header = columns.header;
  const std::vector<int>& used = columns.used;
  const int gravity_columns = columns.gravity_columns;
  std::vector<std::string_view> cells;
  BodyLog log;
  std::vector<double> v(used.size());
  while (lines.Next(line)) {
    if (csv::IsBlank(line)) continue;
    const std::string where = source + ":" + std::to_string(lines.number());
    csv::SplitCells(line, cells);
    if (cells.size() != header.size()) {
      throw CsvError(where + ": " + std::to_string(cells.size()) + " cells, but the header has " +
                     std::to_string(header.size()) + " columns");
    }
    for (size_t k = 0; k < used.size(); ++k) {
      try {
        v[k] = ParseDouble(cells[used[k]], "column " + std::to_string(used[k] + 1) + " '" + header[used[k]] + "'");
      } catch (const InvalidNumber& e) {
        throw CsvError(where + ": " + e.what(), /*invalid_value=*/true);
      }
    }
    TwistWrenchSample s;
    s.t = v[0];
    for (int k = 0; k < 6; ++k) {
      s.twist[k] = v[1 + k];
      s.wrench[k] = v[7 + k];
    }
    if (!log.samples.empty() && !(s.t > log.samples.back().t)) {
      throw CsvError(where + ": time " + std::string(cells[used[0]]) + " does not increase");
    }
    log.samples.push_back(s);
    if (gravity_columns == 3) log.gravity.emplace_back(v[13], v[14], v[15]);
  }
  if (log.samples.size() < 2) throw CsvError(source + ": fewer than 2 data rows");
  Eigen::VectorXd t(static_cast<Eigen::Index>(log.samples.size()));
  for (std::size_t i = 0; i < log.samples.size(); ++i) t[static_cast<Eigen::Index>(i)] = log.samples[i].t;
  ScaleTimeStamps(t, time_scale, source + ": column " + std::to_string(used[0] + 1) + " 't'");
  for (std::size_t i = 0; i < log.samples.size(); ++i) log.samples[i].t = t[static_cast<Eigen::Index>(i)];
  return log;
}

BodyLog ReadBodyCsv(const std::string& path, std::vector<std::string>* notices, double time_scale) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw CsvError(CannotText("read", "", path));
  return ParseBodyCsv(in, path, notices, time_scale);
}

void WriteBodyCsv(const std::string& path, const BodyLog& log) {
  std::vector<std::string> header(std::begin(kColumns), std::end(kColumns));
  const bool gravity = !log.gravity.empty();
  if (gravity) header.insert(header.end(), std::begin(kGravity), std::end(kGravity));
  Eigen::MatrixXd columns(log.samples.size(), header.size());
  for (size_t i = 0; i < log.samples.size(); ++i) {
    const TwistWrenchSample& s = log.samples[i];
    columns(i, 0) = s.t;
    columns.row(i).segment<6>(1) = s.twist.transpose();
    columns.row(i).segment<6>(7) = s.wrench.transpose();
    if (gravity) columns.row(i).segment<3>(13) = log.gravity[i].transpose();
  }
  WriteColumnsCsv(path, header, columns);
}

}  // namespace inertial
