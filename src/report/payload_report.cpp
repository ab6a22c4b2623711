#include "inertial/report/payload_report.hpp"

#include <cmath>

#include "inertial/model/number_text.hpp"
#include "inertial/report/uncertainty_report.hpp"

namespace inertial {
namespace {

std::string X(double v) { return FormatNumberExact(v); }

std::string List(std::initializer_list<double> values) {
  std::string s;
  for (double v : values) s += (s.empty() ? "" : ", ") + X(v);
  return s;
}

nlohmann::json Number(double x) { return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json("inf"); }

}  // namespace

PayloadValues PayloadValuesOf(const InertialParams& payload) {
  return PayloadValues{payload.mass(), payload.com(), payload.rotational_inertia_about_com()};
}

std::optional<PayloadValues> PayloadValuesOf(const PayloadEvent& event) {
  if (!(event.added_mass > 0) || !event.added_pi.allFinite()) return std::nullopt;
  return PayloadValuesOf(InertialParams::FromVector(event.added_pi));
}

std::string UrScriptPayload(const PayloadValues& p) {
  const Matrix3& I = p.inertia_about_com;
  return "set_target_payload(" + X(p.mass) + ", [" + List({p.com.x(), p.com.y(), p.com.z()}) + "], [" +
         List({I(0, 0), I(1, 1), I(2, 2), I(0, 1), I(0, 2), I(1, 2)}) + "])";
}

std::string FrankaSetLoad(const PayloadValues& p) {
  const Matrix3& I = p.inertia_about_com;
  // Column-major: column 0 (I00, I10, I20), then columns 1 and 2.
  return "robot.setLoad(" + X(p.mass) + ", {" + List({p.com.x(), p.com.y(), p.com.z()}) + "}, {" +
         List({I(0, 0), I(1, 0), I(2, 0), I(0, 1), I(1, 1), I(2, 1), I(0, 2), I(1, 2), I(2, 2)}) + "});";
}

std::string UrdfPayloadLink(const PayloadValues& p, const std::string& parent_link) {
  const Matrix3& I = p.inertia_about_com;
  return "<link name=\"payload\">\n"
         "  <inertial>\n"
         "    <origin xyz=\"" + X(p.com.x()) + " " + X(p.com.y()) + " " + X(p.com.z()) + "\" rpy=\"0 0 0\"/>\n"
         "    <mass value=\"" + X(p.mass) + "\"/>\n"
         "    <inertia ixx=\"" + X(I(0, 0)) + "\" ixy=\"" + X(I(0, 1)) + "\" ixz=\"" + X(I(0, 2)) + "\" iyy=\"" +
         X(I(1, 1)) + "\" iyz=\"" + X(I(1, 2)) + "\" izz=\"" + X(I(2, 2)) + "\"/>\n"
         "  </inertial>\n"
         "</link>\n"
         "<joint name=\"payload_joint\" type=\"fixed\">\n"
         "  <parent link=\"" + parent_link + "\"/>\n"
         "  <child link=\"payload\"/>\n"
         "  <origin xyz=\"0 0 0\" rpy=\"0 0 0\"/>\n"
         "</joint>\n";
}

std::string PayloadText(const PayloadIdentification& r) {
  const PayloadValues p = PayloadValuesOf(r.payload);
  std::string s = "payload on " + r.link + " (in its frame), ";
  const BaselinePairing& b = r.pairing;
  s += r.from_difference ? "from the difference with the baseline run (" + std::to_string(r.num_samples) +
                               " paired samples, the baseline shifted by " + FormatNumber(1000 * b.time_shift, 4) +
                               " ms; positions agree to " + FormatNumber(100 * b.position_mismatch, 3) +
                               " % of the range, worst " + b.mismatch_joint + ", " +
                               FormatNumber(100 * b.position_mismatch_unshifted, 3) +
                               " % unshifted; the remaining mismatch's predicted torque " +
                               FormatNumber(100 * b.mismatch_torque, 3) + " % of the difference's)"
                         : "against the model (" + std::to_string(r.num_samples) + " samples; links held at the URDF)";
  s += ", RMS torque residual " + FormatNumber(r.residual_rms, 3) + " N m:\n  ";
  s += BodyUncertaintyText(r.payload, r.uncertainty, &r.held) + "\n";
  s += "  (+- one std: the larger of the white-noise one and the spread of the residual's " +
       std::to_string(r.time_blocks) + " time blocks of " + std::to_string(r.block_length) +
       " samples; the residual is correlated over " + FormatNumber(r.correlation_time, 3) + " samples)\n";
  if (r.plausibility) {
    s += "  " + std::string(r.plausibility->plausible ? "plausible" : "NOT plausible") + ": region from " + r.region +
         ", slack " + FormatNumber(r.plausibility->slack, 3) +
         (r.plausibility->words.empty() ? std::string() : "; " + r.plausibility->words) + "\n";
  }
  if (r.model_error) {
    s += "warning: the residual (" + FormatNumber(r.residual_rms, 3) + " N m RMS) is far above its sample-to-sample "
         "noise (" + FormatNumber(r.residual_white_noise, 3) + " N m): it is mostly smooth in time, i.e. the " +
         (r.from_difference ? std::string("difference holds more than the payload (tracking, friction)")
                            : std::string("model (the URDF's links or the effects) is wrong, not (only) the payload")) +
         ", or the torques were low-passed before logging. The values above are off by that error, by more than "
         "their std can show (the error is alike in every part of the log); " +
         (r.from_difference ? std::string("check the pairing and the runs")
                            : std::string("record the same trajectory without the payload and fit the difference "
                                          "(payload --baseline)")) +
         ".\n";
  }
  s += "Universal Robots (URScript):\n  " + UrScriptPayload(p) + "\n";
  s += "Franka (libfranka, C++):\n  " + FrankaSetLoad(p) + "\n";
  s += "URDF:\n";
  std::string urdf = UrdfPayloadLink(p, r.link);
  for (size_t start = 0; start < urdf.size();) {
    const size_t end = urdf.find('\n', start);
    s += "  " + urdf.substr(start, end - start + 1);
    start = end + 1;
  }
  return s;
}

nlohmann::json PayloadJson(const PayloadIdentification& r) {
  const PayloadValues p = PayloadValuesOf(r.payload);
  const Matrix3& I = p.inertia_about_com;
  const Vector6& u = r.uncertainty.inertia_about_com;  // Ixx Iyy Izz Ixy Iyz Ixz
  nlohmann::json j;
  j["link"] = r.link;
  j["mass"] = p.mass;
  j["mass_std"] = Number(r.uncertainty.mass);
  j["com"] = {p.com.x(), p.com.y(), p.com.z()};
  j["com_std"] = {Number(r.uncertainty.com.x()), Number(r.uncertainty.com.y()), Number(r.uncertainty.com.z())};
  j["inertia_about_com"] = {{"ixx", I(0, 0)}, {"iyy", I(1, 1)}, {"izz", I(2, 2)},
                            {"ixy", I(0, 1)}, {"ixz", I(0, 2)}, {"iyz", I(1, 2)}};
  j["inertia_about_com_std"] = {{"ixx", Number(u[0])}, {"iyy", Number(u[1])}, {"izz", Number(u[2])},
                                {"ixy", Number(u[3])}, {"ixz", Number(u[5])}, {"iyz", Number(u[4])}};
  j["held_by_prior"] = HeldQuantities(r.held);
  j["from_difference"] = r.from_difference;
  if (r.from_difference) {
    j["time_shift"] = r.pairing.time_shift;
    j["position_mismatch"] = r.pairing.position_mismatch;
    j["position_mismatch_joint"] = r.pairing.mismatch_joint;
    j["position_mismatch_unshifted"] = r.pairing.position_mismatch_unshifted;
    j["position_mismatch_unshifted_joint"] = r.pairing.unshifted_joint;
    j["mismatch_torque"] = Number(r.pairing.mismatch_torque);
  }
  j["num_samples"] = r.num_samples;
  j["residual_rms"] = r.residual_rms;
  j["residual_white_noise"] = r.residual_white_noise;
  j["model_error"] = r.model_error;
  if (r.model_error) {
    j["advice"] = r.from_difference ? "the difference's residual is mostly smooth: check the pairing and the runs"
                                    : "the residual is mostly smooth (model error or filtered torques): record the "
                                      "same trajectory without the payload and fit the difference (payload --baseline)";
  }
  j["uncertainty_blocks"] = {{"blocks", r.time_blocks},
                             {"block_length", r.block_length},
                             {"correlation_time", r.correlation_time}};
  if (r.plausibility) {
    j["plausibility"] = {{"region", r.region},          {"slack", r.plausibility->slack},
                         {"inside", r.plausibility->inside}, {"on_edge", r.plausibility->on_edge},
                         {"plausible", r.plausibility->plausible}, {"words", r.plausibility->words}};
  }
  j["ur_script"] = UrScriptPayload(p);
  j["franka"] = FrankaSetLoad(p);
  j["urdf"] = UrdfPayloadLink(p, r.link);
  return j;
}

}  // namespace inertial
