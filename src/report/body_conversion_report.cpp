#include "inertial/report/body_conversion_report.hpp"

#include <sstream>

#include "inertial/model/number_text.hpp"

namespace inertial {

std::string BodyConversionText(const BodyConversion& conversion) {
  const Eigen::MatrixXd& M = conversion.value;
  const std::string indent = "\n" + std::string(conversion.to.size() + 2, ' ');
  std::ostringstream os;
  os << conversion.to << ":";
  for (Eigen::Index i = 0; i < M.rows(); ++i) {
    for (Eigen::Index j = 0; j < M.cols(); ++j) {
      const bool new_row = M.cols() > 1 && i > 0 && j == 0;
      os << (new_row ? indent : std::string(" ")) << FormatNumber(M(i, j) + 0.0, kRoundTripDigits);  // + 0.0 turns -0 into 0
    }
  }
  os << "\n";
  return os.str();
}

nlohmann::json BodyConversionJson(const BodyConversion& conversion) {
  const Eigen::MatrixXd& M = conversion.value;
  nlohmann::json value = nlohmann::json::array();
  for (Eigen::Index i = 0; i < M.rows(); ++i) {
    if (M.cols() == 1) {
      value.push_back(M(i, 0));
      continue;
    }
    nlohmann::json row = nlohmann::json::array();
    for (Eigen::Index j = 0; j < M.cols(); ++j) row.push_back(M(i, j));
    value.push_back(row);
  }
  const ConsistencyReport& r = conversion.consistency;
  nlohmann::json j;
  j[conversion.to] = value;
  j["consistency"] = {{"fully_consistent", conversion.consistent},
                      {"margins_above_tolerance", r.fully_consistent()},
                      {"mass", r.mass},
                      {"min_inertia_eigenvalue_com", r.min_inertia_eigenvalue_com},
                      {"min_triangle_margin", r.min_triangle_margin},
                      {"min_pseudo_inertia_eigenvalue", r.min_pseudo_inertia_eigenvalue},
                      {"reason", r.reason}};
  return j;
}

std::string BodyConversionNote(const BodyConversion& conversion) {
  const ConsistencyReport& r = conversion.consistency;
  if (r.fully_consistent()) return "";
  if (!conversion.consistent) return "warning: " + r.reason + "\n";
  return "note: consistent by construction (finite theta), but so thin that the numerical check cannot confirm it: " +
         r.reason + "\n";
}

}  // namespace inertial
