#include "inertial/report/run_errors_report.hpp"

#include <sstream>

#include "inertial/model/number_text.hpp"

namespace inertial {
namespace {

nlohmann::json PerChannel(const std::vector<std::string>& channels, const Eigen::VectorXd& v, double total) {
  nlohmann::json j = nlohmann::json::object();
  for (size_t k = 0; k < channels.size(); ++k) j[channels[k]] = v[static_cast<Eigen::Index>(k)];
  j["total"] = total;
  return j;
}

}  // namespace

std::string RunErrorsText(const std::vector<std::string>& names, const std::vector<ModelComparison>& runs,
                          const std::string& what) {
  if (runs.size() < 2) return "";
  std::ostringstream out;
  out << what << ", run by run:\n";
  for (size_t k = 0; k < runs.size(); ++k) {
    const ModelComparison& c = runs[k];
    Eigen::Index worst = 0;
    c.errors.rms.maxCoeff(&worst);
    out << "  " << names[k] << " (" << c.predicted.rows() << " samples): RMS " << FormatNumber(c.errors.total_rms, 4) << " "
        << c.unit << " (" << FormatFixed(100.0 * c.errors.total_relative_rms, 2) << " %); worst "
        << c.channels[static_cast<size_t>(worst)] << " " << FormatNumber(c.errors.rms[worst], 4) << " " << c.unit << "\n";
  }
  return out.str();
}

nlohmann::json RunErrorsJson(const std::vector<std::string>& names, const std::vector<ModelComparison>& runs) {
  nlohmann::json j = nlohmann::json::array();
  for (size_t k = 0; k < runs.size(); ++k) {
    const ModelComparison& c = runs[k];
    j.push_back({{"run", names[k]},
                 {"samples", c.predicted.rows()},
                 {"rms", PerChannel(c.channels, c.errors.rms, c.errors.total_rms)},
                 {"relative_rms", PerChannel(c.channels, c.errors.relative_rms, c.errors.total_relative_rms)}});
  }
  return j;
}

}  // namespace inertial
