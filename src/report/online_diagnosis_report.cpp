#include "inertial/report/online_diagnosis_report.hpp"
#include "inertial/model/number_text.hpp"

#include <cmath>
#include <cstdio>
#include <sstream>

namespace inertial {
namespace {

std::string Percent(double share) { return FormatFixed(100.0 * share, 1) + " %"; }

std::string Evidence(const CandidateEvidence& e) {
  std::string s;
  auto add = [&](bool on, const char* what) {
    if (on) s += (s.empty() ? "" : ", ") + std::string(what);
  };
  add(e.by_size, "held-out size");
  add(e.by_significance, "significance");
  add(e.by_plausibility, "plausibility");
  return s.empty() ? "none" : s;
}

bool Suggested(const OnlineCandidate& c) { return c.evidence.suggested() && c.alternative_to.empty(); }

nlohmann::json CandidateJson(const OnlineCandidate& c) {
  nlohmann::json j = {{"effect", std::string(ToString(c.kind))},
                      {"name", c.name},
                      {"item", c.item},
                      {"explained", c.evidence.explained},
                      {"significance", c.evidence.significance},
                      {"threshold", c.evidence.threshold},
                      {"restored", c.evidence.restored},
                      {"score", c.evidence.score},
                      {"evidence", Evidence(c.evidence)},
                      {"rms_before", c.rms_before},
                      {"rms_after", c.rms_after},
                      {"values", c.values},
                      {"explanation", OnlineCandidateExplanation(c)}};
  if (!c.joint.empty()) j["joint"] = c.joint;
  if (!c.link.empty()) j["link"] = c.link;
  if (!c.replaces.empty()) j["replaces"] = c.replaces;
  if (!c.alternative_to.empty()) j["alternative_to"] = c.alternative_to;
  return j;
}

}  // namespace

std::string OnlineCandidateExplanation(const OnlineCandidate& c) {
  const std::string& j = c.joint;
  const double v0 = c.values.empty() ? 0.0 : c.values[0];
  const double v1 = c.values.size() > 1 ? c.values[1] : 0.0;
  const std::string fall = " (its RMS " + FormatNumber(c.rms_before, 3) + " -> " + FormatNumber(c.rms_after, 3) + " N m)";
  switch (c.kind) {
    case EffectKind::kCoulomb:
      return "the " + j + " residual steps where the velocity changes sign" + fall + ": Coulomb (dry) friction of " +
             FormatNumber(v0, 3) + " N m is missing";
    case EffectKind::kViscous:
      return "the " + j + " residual grows in proportion to velocity" + fall + ": viscous friction b = " + FormatNumber(v0, 3) +
             " N m s/rad is missing";
    case EffectKind::kOffset:
      return "the " + j + " residual has a constant part" + fall + ": a torque-sensor offset of " + FormatNumber(v0, 3) +
             " N m is missing";
    case EffectKind::kArmature:
      return "the " + j + " residual follows the acceleration" + fall + ": reflected rotor inertia (armature) Ia = " +
             FormatNumber(v0, 3) + " kg m^2 is missing";
    case EffectKind::kSpring:
      return "the " + j + " residual grows with position" + fall + ": a spring k = " + FormatNumber(v0, 3) + " N m/rad about q0 = " +
             FormatNumber(v1, 3) + " rad is missing";
    case EffectKind::kAsymmetric:
      return "the " + j + " residual steps by different amounts in the two directions" + fall + ": dry friction of " +
             FormatNumber(v0, 3) + " N m for positive velocity and " + FormatNumber(v1, 3) + " N m for negative is missing" +
             (c.replaces.empty() ? "" : " (in place of " + c.replaces + ")");
    case EffectKind::kPayload: {
      const double m = v0;
      const std::string com = m > 0.0 && c.values.size() >= 4
                                  ? "[" + FormatNumber(c.values[1] / m, 3) + ", " + FormatNumber(c.values[2] / m, 3) + ", " + FormatNumber(c.values[3] / m, 3) + "]"
                                  : "[]";
      return c.link + " is estimated heavier than its URDF beyond the tolerance: a payload of " + FormatNumber(m, 3) +
             " kg with its centre of mass at " + com + " m (link frame), within the robot's reach of it, takes it back to its URDF (or that URDF is wrong)";
    }
    default:
      return c.name;
  }
}

std::string OnlineDiagnosisText(const OnlineDiagnosisResult& r) {
  std::ostringstream out;
  out << "Online diagnosis (prequential: every sample predicted before it is learned from), " << r.samples
      << " samples over the last " << FormatNumber(r.window_seconds, 3) << " s: model RMS " << FormatNumber(r.model.total_rms, 3) << " N m ("
      << Percent(r.model.total_relative_rms) << ")\n";
  for (const std::string& note : r.notes) out << "  note: " << note << "\n";
  if (!r.bent_links.empty()) {
    out << "  links beyond the tolerance of their URDF:";
    for (const std::string& l : r.bent_links) out << " " << l;
    out << "\n";
  }
  if (r.num_suggestions == 0) {
    out << "  No missing effect suggested.\n";
  } else {
    out << "  Missing effects, best first:\n";
  }
  int shown = 0;
  for (size_t i = 0; i < r.candidates.size(); ++i) {
    const OnlineCandidate& c = r.candidates[i];
    if (Suggested(c)) {
      // A payload explains a bent link, not the error: it and its link share the link's columns, so
      // the prediction is the same with either (held_payload_fit.hpp).
      out << "  " << ++shown << ". " << c.item << ": "
          << (c.kind == EffectKind::kPayload
                  ? "restores " + Percent(c.evidence.restored) + " of the links' plausibility (the same torques: a payload and its link share their columns)"
                  : "explains " + Percent(c.evidence.explained) + " of the held-out error")
          << " [" << Evidence(c.evidence) << "]\n     " << OnlineCandidateExplanation(c) << "\n";
    }
  }
  int next = 0;
  for (const OnlineCandidate& c : r.candidates) {
    if (Suggested(c) || next >= 3) continue;
    if (next++ == 0) out << "  not suggested (next best):\n";
    out << "    " << c.name << ": explains " << Percent(c.evidence.explained)
        << (c.alternative_to.empty() ? "" : "; an alternative to " + c.alternative_to) << "\n";
  }
  return out.str();
}

nlohmann::json OnlineDiagnosisJson(const OnlineDiagnosisResult& r) {
  nlohmann::json suggestions = nlohmann::json::array(), others = nlohmann::json::array();
  for (const OnlineCandidate& c : r.candidates) (Suggested(c) ? suggestions : others).push_back(CandidateJson(c));
  return {{"samples", r.samples},
          {"window_s", r.window_seconds},
          {"rms", r.model.total_rms},
          {"relative_rms", r.model.total_relative_rms},
          {"suggestions", suggestions},
          {"candidates", others},
          {"bent_links", r.bent_links},
          {"implausibility", r.implausibility},
          {"notes", r.notes}};
}

}  // namespace inertial
