#include "inertial/formats/estimator_state_file.hpp"
#include "inertial/formats/file_error.hpp"
#include "inertial/formats/input_file.hpp"
#include "inertial/formats/json_integer.hpp"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include <fcntl.h>
#include <unistd.h>

namespace inertial {
namespace {

constexpr const char* kFormat = "inertial-estimator-state";
constexpr int kVersion = 1;

// A matrix as a JSON array of its rows.
nlohmann::json RowsJson(const Eigen::MatrixXd& m) {
  nlohmann::json rows = nlohmann::json::array();
  for (int r = 0; r < m.rows(); ++r) {
    std::vector<double> row(m.cols());
    for (int c = 0; c < m.cols(); ++c) row[c] = m(r, c);
    rows.push_back(row);
  }
  return rows;
}

}  // namespace

std::string EstimatorStateToJson(const EstimatorState& s, const std::string& model_description) {
  nlohmann::json j;
  j["format"] = kFormat;
  j["version"] = kVersion;
  j["kind"] = s.kind;
  j["model"] = model_description;
  j["x"] = std::vector<double>(s.x.data(), s.x.data() + s.x.size());
  j["P"] = RowsJson(s.P);
  if (s.statistics.size() > 0) {  // the online fit's sufficient statistics (online_fit.hpp)
    j["statistics"] = RowsJson(s.statistics);
    j["statistics_samples"] = s.statistics_samples;
    j["solved"] = s.solved;
  }
  if (s.directions.size() > 0) {  // the gradient law's last direction (gradient_estimator.hpp)
    j["directions"] = std::vector<double>(s.directions.data(), s.directions.data() + s.directions.size());
  }
  j["has_time"] = s.has_time;
  j["last_time"] = s.last_time;
  nlohmann::json counters = nlohmann::json::object();
  for (int k = 0; k < kNumUpdateStatuses; ++k) counters[std::string(ToString(static_cast<UpdateStatus>(k)))] = s.counters.count[k];
  j["counters"] = counters;
  return j.dump() + "\n";
}

EstimatorState EstimatorStateFromJson(const std::string& text, const std::string& source, std::string* model) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {  // a parse error, or a number that overflows (1e400)
    throw StateFileError(source + ": not an estimator state: " + e.what());
  }
  try {
    if (!j.is_object() || j.value("format", "") != kFormat) {
      throw StateFileError(source + ": not an estimator state (no \"format\": \"" + kFormat + "\")");
    }
    const nlohmann::json& version = j.at("version");
    const std::optional<std::int64_t> v = JsonInteger(version, 1, 1000000);
    if (!v) throw StateFileError(source + ": \"version\" " + NotAnIntegerText(version, 1, 1000000));
    if (*v != kVersion) {
      throw StateFileError(source + ": estimator state version " + std::to_string(*v) + ", this program reads version " +
                           std::to_string(kVersion));
    }
    EstimatorState s;
    s.kind = j.at("kind").get<std::string>();
    if (model != nullptr) *model = j.value("model", "");
    const std::vector<double> x = j.at("x").get<std::vector<double>>();
    s.x = Eigen::Map<const Eigen::VectorXd>(x.data(), static_cast<Eigen::Index>(x.size()));
    const auto& P = j.at("P");
    if (!P.empty()) {
      if (P.size() != x.size()) throw StateFileError(source + ": covariance has " + std::to_string(P.size()) + " rows for " + std::to_string(x.size()) + " parameters");
      s.P.resize(static_cast<Eigen::Index>(x.size()), static_cast<Eigen::Index>(x.size()));
      for (size_t r = 0; r < P.size(); ++r) {
        const std::vector<double> row = P[r].get<std::vector<double>>();
        if (row.size() != x.size()) throw StateFileError(source + ": covariance row " + std::to_string(r) + " has " + std::to_string(row.size()) + " entries");
        for (size_t c = 0; c < row.size(); ++c) s.P(r, c) = row[c];
      }
    }
    if (j.contains("statistics")) {
      const auto& M = j.at("statistics");
      if (!M.is_array()) throw StateFileError(source + ": \"statistics\" is not an array of rows");
      const size_t n = M.size();
      s.statistics.resize(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(n));
      for (size_t r = 0; r < n; ++r) {
        const std::vector<double> row = M[r].get<std::vector<double>>();
        if (row.size() != n) {
          throw StateFileError(source + ": statistics row " + std::to_string(r) + " has " + std::to_string(row.size()) +
                               " entries, not " + std::to_string(n));
        }
        for (size_t c = 0; c < n; ++c) s.statistics(r, c) = row[c];
      }
      s.statistics_samples = j.at("statistics_samples").get<double>();
      s.solved = j.at("solved").get<bool>();
    }
    if (j.contains("directions")) {
      const std::vector<double> d = j.at("directions").get<std::vector<double>>();
      s.directions = Eigen::Map<const Eigen::VectorXd>(d.data(), static_cast<Eigen::Index>(d.size()));
    }
    s.has_time = j.at("has_time").get<bool>();
    s.last_time = j.at("last_time").get<double>();
    const auto& counters = j.at("counters");
    if (!counters.is_object()) throw StateFileError(source + ": \"counters\" is not an object");
    for (int k = 0; k < kNumUpdateStatuses; ++k) {
      const std::string name(ToString(static_cast<UpdateStatus>(k)));
      if (!counters.contains(name)) continue;
      const std::optional<std::uint64_t> count = JsonUnsigned(counters.at(name), UINT64_MAX);
      if (!count) {
        throw StateFileError(source + ": counter \"" + name + "\" " + NotAnIntegerText(counters.at(name), 0, UINT64_MAX));
      }
      s.counters.count[k] = *count;
    }
    return s;
  } catch (const nlohmann::json::exception& e) {
    throw StateFileError(source + ": malformed estimator state: " + e.what());
  }
}

void SaveEstimatorState(const std::string& path, const EstimatorState& state, const std::string& model_description) {
  // Written to a temporary file, flushed to the disk (fsync), renamed over the target, and the
  // directory flushed too: a kill leaves the old or the new state, and so does a power cut.
  const std::string tmp = path + ".tmp";
  const std::string text = EstimatorStateToJson(state, model_description);
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throw StateFileError(CannotText("write", "estimator state", tmp));
  std::size_t written = 0;
  while (written < text.size()) {
    const ssize_t n = ::write(fd, text.data() + written, text.size() - written);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const std::string why = std::strerror(errno);
      ::close(fd);
      ::unlink(tmp.c_str());
      throw StateFileError(tmp + ": cannot write the estimator state: " + why);
    }
    written += static_cast<std::size_t>(n);
  }
  if (::fsync(fd) != 0 || ::close(fd) != 0) {
    const std::string why = std::strerror(errno);
    ::unlink(tmp.c_str());
    throw StateFileError(tmp + ": cannot flush the estimator state to disk: " + why);
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    const std::string why = std::strerror(errno);
    ::unlink(tmp.c_str());
    throw StateFileError(path + ": cannot replace the estimator state: " + why);
  }
  const std::filesystem::path parent = std::filesystem::path(path).parent_path();
  const int dir = ::open(parent.empty() ? "." : parent.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dir >= 0) {
    ::fsync(dir);  // the rename itself on disk; a file system that cannot sync a directory still has the file
    ::close(dir);
  }
}

EstimatorState LoadEstimatorState(const std::string& path, std::string* model_description) {
  std::string text;
  try {
    text = ReadInputFile(path, "estimator state", kMaxStateFileBytes);
  } catch (const InputFileError& e) {
    throw StateFileError(e.what());
  }
  return EstimatorStateFromJson(text, path, model_description);
}

}  // namespace inertial
