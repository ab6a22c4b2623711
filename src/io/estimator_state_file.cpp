#include "inertial/io/estimator_state_file.hpp"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

namespace inertial {
namespace {

constexpr const char* kFormat = "inertial-estimator-state";
constexpr int kVersion = 1;

}  // namespace

std::string EstimatorStateToJson(const EstimatorState& s, const std::string& model_description) {
  nlohmann::json j;
  j["format"] = kFormat;
  j["version"] = kVersion;
  j["kind"] = s.kind;
  j["model"] = model_description;
  j["x"] = std::vector<double>(s.x.data(), s.x.data() + s.x.size());
  nlohmann::json P = nlohmann::json::array();
  for (int r = 0; r < s.P.rows(); ++r) {
    std::vector<double> row(s.P.cols());
    for (int c = 0; c < s.P.cols(); ++c) row[c] = s.P(r, c);
    P.push_back(row);
  }
  j["P"] = P;
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
  } catch (const nlohmann::json::parse_error& e) {
    throw StateFileError(source + ": not an estimator state: " + e.what());
  }
  try {
    if (!j.is_object() || j.value("format", "") != kFormat) {
      throw StateFileError(source + ": not an estimator state (no \"format\": \"" + kFormat + "\")");
    }
    if (j.at("version").get<int>() != kVersion) {
      throw StateFileError(source + ": estimator state version " + std::to_string(j.at("version").get<int>()) +
                           ", this program reads version " + std::to_string(kVersion));
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
    s.has_time = j.at("has_time").get<bool>();
    s.last_time = j.at("last_time").get<double>();
    const auto& counters = j.at("counters");
    for (int k = 0; k < kNumUpdateStatuses; ++k) {
      s.counters.count[k] = counters.value(std::string(ToString(static_cast<UpdateStatus>(k))), std::uint64_t{0});
    }
    return s;
  } catch (const nlohmann::json::exception& e) {
    throw StateFileError(source + ": malformed estimator state: " + e.what());
  }
}

void SaveEstimatorState(const std::string& path, const EstimatorState& state, const std::string& model_description) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw StateFileError(tmp + ": cannot write the estimator state: " + std::strerror(errno));
    out << EstimatorStateToJson(state, model_description);
    out.flush();
    if (!out) throw StateFileError(tmp + ": cannot write the estimator state: " + std::strerror(errno));
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    throw StateFileError(path + ": cannot replace the estimator state: " + std::strerror(errno));
  }
}

EstimatorState LoadEstimatorState(const std::string& path, std::string* model_description) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw StateFileError(path + ": cannot open the estimator state: " + std::strerror(errno));
  std::ostringstream text;
  text << in.rdbuf();
  return EstimatorStateFromJson(text.str(), path, model_description);
}

}  // namespace inertial
