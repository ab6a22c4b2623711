#include "inertial/report/validation_report.hpp"

#include <cmath>
#include <cstdio>
#include <sstream>

#include "inertial/inertia/consistency.hpp"
#include "inertial/report/diagnosis_html.hpp"
#include "inertial/report/diagnosis_report.hpp"
#include "inertial/report/identification_report.hpp"
#include "inertial/report/run_errors_report.hpp"
#include "inertial/model/number_text.hpp"

namespace inertial {
namespace {

std::string Percent(double share) { return std::isfinite(share) ? FormatFixed(100.0 * share, 2) + " %" : "n/a"; }

nlohmann::json PerChannel(const std::vector<std::string>& channels, const Eigen::VectorXd& v, double total) {
  nlohmann::json j = nlohmann::json::object();
  for (std::size_t k = 0; k < channels.size(); ++k) j[channels[k]] = v[static_cast<int>(k)];
  j["total"] = total;
  return j;
}

}  // namespace

ModelValidation ValidateJointModel(const RobotDynamics& model, const Eigen::VectorXd& x, const JointSamples& data) {
  ModelValidation v;
  static_cast<ModelComparison&>(v) = CompareJointModel(model, x, data);
  bool consistent = true;
  v.model_json["bodies"] = BodiesJson(model, x, &consistent);
  v.model_json["effects"] = EffectsJson(model, x);
  v.physically_consistent = consistent;
  return v;
}

ModelValidation ValidateBodyModel(const BodyEffectModel& model, const Eigen::VectorXd& x, const BodyLog& data) {
  ModelValidation v;
  static_cast<ModelComparison&>(v) = CompareBodyModel(model, x, data);
  const InertialParams body = model.Body(x);
  const ConsistencyReport report = CheckConsistency(body);
  v.physically_consistent = report.fully_consistent();
  const Vector10 pi = body.vector();
  v.model_json["body"] = {{"mass", body.mass()},
                          {"com", body.mass() > 0 ? std::vector<double>{body.com().x(), body.com().y(), body.com().z()}
                                                  : std::vector<double>{0, 0, 0}},
                          {"pi", std::vector<double>(pi.data(), pi.data() + 10)},
                          {"physically_consistent", v.physically_consistent}};
  nlohmann::json effects = nlohmann::json::array();
  for (int k = 0; k < static_cast<int>(model.effects().size()); ++k) {
    const Eigen::VectorXd e = model.EffectValues(k, x);
    effects.push_back({{"effect", std::string(ToString(model.effects()[k]))},
                       {"values", std::vector<double>(e.data(), e.data() + e.size())}});
  }
  v.model_json["effects"] = effects;
  return v;
}

std::string ValidationText(const ModelValidation& v) {
  std::ostringstream out;
  out << "Validation of " << v.model_source << " on " << v.data_source << " (" << v.predicted.rows()
      << (v.unit == "N m" ? " samples" : " sample pairs") << "; no fit: the model as stated)\n";
  out << "RMS error (predicted - measured) and relative RMS (over the RMS of the measurement):\n";
  for (std::size_t k = 0; k < v.channels.size(); ++k) {
    out << "  " << v.channels[k] << ": " << FormatNumber(v.errors.rms[static_cast<int>(k)], 4) << " ("
        << Percent(v.errors.relative_rms[static_cast<int>(k)]) << ")\n";
  }
  out << "  all: " << FormatNumber(v.errors.total_rms, 4) << " (" << Percent(v.errors.total_relative_rms) << ") " << v.unit << "\n";
  if (v.left_out > 0) {
    out << "  left out: " << v.left_out << " samples whose measurement or prediction is not finite, e.g.\n";
    for (const std::string& r : v.left_out_reasons) out << "    " << r << "\n";
  }
  out << RunErrorsText(v.run_names, v.runs, "The same");
  out << "\n";
  out << WhereItFailsText(v.channels, v.residuals, "residual of the model") << "\n";
  out << (v.physically_consistent ? "Every body of the model is physically consistent.\n"
                                  : "SOME BODY OF THE MODEL IS NOT PHYSICALLY CONSISTENT.\n");
  return out.str();
}

nlohmann::json ValidationJson(const ModelValidation& v) {
  nlohmann::json j = v.model_json;
  j["model"] = v.model_source;
  j["data"] = v.data_source;
  j["samples"] = v.predicted.rows();
  j["rms"] = PerChannel(v.channels, v.errors.rms, v.errors.total_rms);
  j["relative_rms"] = PerChannel(v.channels, v.errors.relative_rms, v.errors.total_relative_rms);
  j["where_it_fails"] = WhereItFailsJson(v.channels, v.residuals);
  j["physically_consistent"] = v.physically_consistent;
  j["left_out"] = {{"samples", v.left_out}, {"reasons", v.left_out_reasons}};
  if (v.runs.size() > 1) j["runs"] = RunErrorsJson(v.run_names, v.runs);
  return j;
}

void WriteValidationReport(const std::string& directory, const ModelValidation& v, const std::string& text) {
  DiagnosisPlotData p;
  p.title = "inertial validate";
  p.channels = v.channels;
  p.unit = v.unit;
  p.velocity_label = v.unit == "N m" ? "joint velocity [rad/s]" : "matching twist component (wx..wz, vx..vz) [rad/s | m/s]";
  p.t = v.signals.t;
  p.measured = v.signals.tau;
  p.predicted = v.predicted;
  p.velocity = v.signals.qd;
  p.error_labels = {v.model_source};
  p.error_rms = {v.errors.rms};
  const std::vector<std::string> summary{"RMS error of " + v.model_source + " on " + v.data_source + ": " +
                                         FormatNumber(v.errors.total_rms, 4) + " " + v.unit + " (" +
                                         Percent(v.errors.total_relative_rms) + " of the measurement's RMS)."};
  WriteDiagnosisHtml(directory, p, summary, {}, text);
}

}  // namespace inertial
