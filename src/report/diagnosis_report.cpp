#include "inertial/report/diagnosis_report.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "inertial/inertia/consistency.hpp"
#include "inertial/report/diagnosis_html.hpp"
#include "inertial/report/identification_report.hpp"
#include "inertial/report/run_errors_report.hpp"
#include "inertial/model/number_text.hpp"

namespace inertial {
namespace {

// Significant digits (number_text.hpp), a zero shown without its sign.
std::string F(double x, int significant_digits = 3) { return FormatNumber(x == 0.0 ? 0.0 : x, significant_digits); }

// One decimal; a share that rounds to zero prints "0.0 %", never "-0.0 %".
std::string Percent(double share) {
  if (!std::isfinite(share)) return "n/a";
  return (std::abs(100.0 * share) < 0.05 ? std::string("0.0") : FormatFixed(100.0 * share, 1)) + " %";
}

int DofIndex(const RobotDynamics& model, const std::string& joint) {
  for (int k = 0; k < model.num_dofs(); ++k) {
    if (model.dof_names()[k] == joint) return k;
  }
  return -1;
}

const char* kWrenchChannels[6] = {"mx", "my", "mz", "fx", "fy", "fz"};

nlohmann::json Channels(const Eigen::VectorXd& v, double total) {
  nlohmann::json j = nlohmann::json::object();
  for (int k = 0; k < 6; ++k) j[kWrenchChannels[k]] = v[k];
  j["total"] = total;
  return j;
}

std::string Vec3(const Eigen::VectorXd& v, int start = 0) {
  return "[" + F(v[start]) + ", " + F(v[start + 1]) + ", " + F(v[start + 2]) + "]";
}

// "  name: prior -> fit" rows of an error table.
void ErrorTable(std::ostringstream& out, const std::vector<std::string>& names, const TorqueErrors& before,
                const TorqueErrors& after, const std::string& unit) {
  for (size_t k = 0; k < names.size(); ++k) {
    out << "  " << names[k] << ": " << F(before.rms[k], 4) << " (" << Percent(before.relative_rms[k]) << ") -> "
        << F(after.rms[k], 4) << " (" << Percent(after.relative_rms[k]) << ") " << unit << "\n";
  }
  out << "  all: " << F(before.total_rms, 4) << " (" << Percent(before.total_relative_rms) << ") -> "
      << F(after.total_rms, 4) << " (" << Percent(after.total_relative_rms) << ") " << unit << "\n";
}

// Why the held-out data do not support a candidate (explained_error.hpp's three conditions).
std::string NotSuggested(const TorqueErrors& without, const TorqueErrors& with, double explained, double min_explained,
                         double min_gain) {
  const std::string prefix = "not supported: ";
  if (explained < 0.0) {
    return prefix + "it makes the held-out error worse by " + Percent(-explained) +
           " (it fits noise or another effect on the training data)";
  }
  if (explained < min_explained) return prefix + "it removes only " + Percent(explained) + " of the error";
  if (!(with.total_rms < without.total_rms)) {
    return prefix + "it removes " + Percent(explained) + " on average over joints, but the pooled error rises (" +
           F(without.total_rms, 4) + " -> " + F(with.total_rms, 4) + ")";
  }
  return prefix + "no joint's error falls by " + Percent(min_gain) + " of its torque (" + Percent(explained) +
         " of a residual that small is not a missing effect)";
}

// Why the evidence does not support a candidate (candidate_evidence.hpp's routes 1 and 2).
std::string WhyNot(const CandidateEvidence& e, const TorqueErrors& without, const TorqueErrors& with,
                   double min_explained, double min_gain, bool rare) {
  std::string why;
  if (!e.size_conditions) {
    why = NotSuggested(without, with, e.explained, (rare ? 2.0 : 1.0) * min_explained, min_gain);
  } else {
    why = "not supported: it removes " + Percent(e.explained) + " of the held-out error, but its gain counted in "
          "independent samples (" + F(e.significance, 3) + ") is " +
          (e.size_bar > 0.0 ? "below " + F(e.size_bar, 3) : std::string("not positive")) +
          " (the residual is coloured: its samples are not independent)";
  }
  if (e.significance < e.threshold) {
    why += "; significance " + F(e.significance, 3) + " < " + F(e.threshold, 3);
  } else if (e.explained < kMinSignificantShare) {
    why += "; significant (" + F(e.significance, 3) + " >= " + F(e.threshold, 3) + ") but below " +
           Percent(kMinSignificantShare) + " of the error";
  }
  if (rare) why += " (a spring needs both the held-out size and the significance)";
  return why;
}

// Why a robot candidate is not suggested, all evidence considered (candidate_evidence.hpp).
std::string CandidateNotSuggested(const JointDiagnosis& d, const CandidateResult& r, double min_explained,
                                  double min_gain) {
  if (!d.fit.lm.converged()) return "not suggested: the model's own fit did not converge (see the note)";
  if (!r.alternative_to.empty()) {
    return "an alternative to " + r.alternative_to + ": refitted together with it, it adds nothing (both explain the "
           "same residual or straighten the same link)";
  }
  const CandidateEvidence& e = r.evidence;
  std::string why = WhyNot(e, d.fit_validation, r.validation, min_explained, min_gain, r.spec.kind == EffectKind::kSpring);
  const bool bends = r.implausibility > d.implausibility + kMaxBend * std::log1p(d.prior_tolerance);
  if (d.implausibility > 0.0 && !bends) {
    why += "; restores " + Percent(e.restored) + " of the links' plausibility (50 % needed)";
  }
  if (bends) why += "; it bends the links further";
  return why;
}

// What a suggestion is supported by, in words.
std::string Evidence(const CandidateEvidence& e) {
  std::vector<std::string> parts;
  if (e.by_size) parts.push_back("explains " + Percent(e.explained) + " of the held-out error");
  if (e.by_significance) {
    parts.push_back("significance " + F(e.significance, 3) + " >= " + F(e.threshold, 3) +
                    " (held-out gain in independent samples)");
  }
  if (e.by_plausibility) parts.push_back("restores " + Percent(e.restored) + " of the links' plausibility");
  std::string s;
  for (size_t i = 0; i < parts.size(); ++i) s += (i > 0 ? "; " : "") + parts[i];
  return s;
}

// The score the ranking used, as shown (candidate_evidence.hpp: by group).
std::string ScoreText(const CandidateEvidence& e) {
  return FormatFixed(100.0 * e.score, 1) == "-0.0" ? "0.0" : FormatFixed(100.0 * e.score, 1);
}

// "thigh identified at 8.5 kg, URDF 1.3 kg; COM moved 12 mm; inertia changed by 310 %".
std::string Departure(const InertialParams& body, const InertialParams& prior, const BodyPlausibility& p) {
  std::string s = F(body.mass(), 3) + " kg (URDF " + F(prior.mass(), 3) + " kg)";
  if (p.com_shift > 0.0) s += ", COM moved " + F(1000.0 * p.com_shift, 3) + " mm";
  s += ", inertia about the COM changed by " + Percent(p.inertia_change);
  return s;
}

}  // namespace

std::string PlausibilityText(const RobotDynamics& model, const JointDiagnosis& d) {
  std::ostringstream out;
  out << "Identified bodies against their URDF (tolerance: within a factor " << F(1.0 + d.prior_tolerance, 3)
      << ", departures counted beyond " << F(kDepartureMargin, 6) << " standard deviations of the estimate)\n";
  std::vector<std::string> bent;
  for (size_t e = 0; e < d.plausibility.size() && e < model.bodies().size(); ++e) {
    const BodyPlausibility& p = d.plausibility[e];
    const int i = static_cast<int>(e);
    Eigen::VectorXd x_prior = d.fit.x;
    x_prior.segment<10>(10 * i).setZero();
    const InertialParams body = model.BodyInertia(i, d.fit.x), prior = model.BodyInertia(i, x_prior);
    const bool is_link = e < d.links.size() && d.links[e];
    const bool held = e < d.frozen_bodies.size() && d.frozen_bodies[e];
    out << "  " << model.bodies()[e].name << ": mass x" << F(p.mass_ratio, 3) << ", COM "
        << F(1000.0 * p.com_shift, 3) << " mm, principal moments x" << F(p.moment_ratios[0], 2) << " x"
        << F(p.moment_ratios[1], 2) << " x" << F(p.moment_ratios[2], 2) << ", divergence "
        << F(p.divergence, 3) << ", factor " << F(p.factor, 3)
        << (held ? " (held at the URDF)" : (!is_link ? " (not a link: no URDF to compare)"
                                                     : (p.Within(d.prior_tolerance) ? "" : "  BENT")))
        << "\n";
    if (is_link && !held && !p.Within(d.prior_tolerance)) {
      bent.push_back(model.bodies()[e].name + " identified at " + Departure(body, prior, p) +
                     ": something the model lacks is being imitated by this link (or its URDF is wrong)");
    }
  }
  for (const std::string& b : bent) out << "  ! " << b << "\n";
  return out.str();
}

nlohmann::json PlausibilityJson(const RobotDynamics& model, const JointDiagnosis& d) {
  nlohmann::json bodies = nlohmann::json::array();
  for (size_t e = 0; e < d.plausibility.size() && e < model.bodies().size(); ++e) {
    const BodyPlausibility& p = d.plausibility[e];
    const int i = static_cast<int>(e);
    Eigen::VectorXd x_prior = d.fit.x;
    x_prior.segment<10>(10 * i).setZero();
    const bool is_link = e < d.links.size() && d.links[e];
    auto finite = [](double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json("inf"); };
    bodies.push_back({{"name", model.bodies()[e].name},
                      {"mass", model.BodyInertia(i, d.fit.x).mass()},
                      {"mass_prior", model.BodyInertia(i, x_prior).mass()},
                      {"mass_ratio", finite(p.mass_ratio)},
                      {"com_shift_mm", finite(1000.0 * p.com_shift)},
                      {"com_shift_relative", finite(p.com_shift_relative)},
                      {"principal_moment_ratios", {p.moment_ratios[0], p.moment_ratios[1], p.moment_ratios[2]}},
                      {"inertia_change", finite(p.inertia_change)},
                      {"divergence", finite(p.divergence)},
                      {"factor", finite(p.factor)},
                      {"raw_factor", finite(p.raw_factor)},
                      {"link", is_link},
                      {"within_tolerance", !is_link || p.Within(d.prior_tolerance)}});
  }
  return bodies;
}

std::string WhereItFailsText(const std::vector<std::string>& dof_names, const ResidualAnalysis& residuals,
                             const std::string& what) {
  std::ostringstream out;
  out << "Where it fails (" << what << ")\n  worst 1 s windows:";
  for (const ResidualWindow& w : residuals.worst_windows) {
    out << " t = " << FormatFixed(w.t_start, 1) << "-" << FormatFixed(w.t_end, 1) << " s RMS " << F(w.rms) << " (worst "
        << dof_names[w.worst_joint] << ");";
  }
  out << "\n  residual ~ c0 + c1 sign(qd) + c2 qd + c3 qdd + c4 (q - mean q), per joint (and its slope on tau alone):\n";
  for (int k = 0; k < static_cast<int>(dof_names.size()); ++k) {
    const JointResidualSignature& s = residuals.joints[k];
    out << "  " << dof_names[k] << ": RMS " << F(s.rms) << "; c0 " << F(s.coefficients[kResidualMean])
        << ", step at reversal " << F(2 * s.coefficients[kVelocitySign]) << ", c2 " << F(s.coefficients[kVelocity])
        << ", c3 " << F(s.coefficients[kAcceleration]) << ", c4 " << F(s.coefficients[kPosition]) << " (explains "
        << Percent(s.explained) << "); slope on tau " << F(s.alone[kTorque]) << "\n";
  }
  return out.str();
}

nlohmann::json WhereItFailsJson(const std::vector<std::string>& dof_names, const ResidualAnalysis& residuals) {
  nlohmann::json windows = nlohmann::json::array();
  for (const ResidualWindow& w : residuals.worst_windows) {
    windows.push_back({{"t_start", w.t_start}, {"t_end", w.t_end}, {"rms", w.rms},
                       {"worst_joint", dof_names[w.worst_joint]}});
  }
  nlohmann::json joints = nlohmann::json::object();
  const char* names[kResidualSignals] = {"mean", "velocity_sign", "velocity", "acceleration", "position", "torque"};
  for (int k = 0; k < static_cast<int>(dof_names.size()); ++k) {
    const JointResidualSignature& s = residuals.joints[k];
    nlohmann::json correlations = nlohmann::json::object();
    for (int q = 1; q < kResidualSignals; ++q) correlations[names[q]] = s.correlations[q];
    joints[dof_names[k]] = {{"rms", s.rms},
                                    {"mean", s.coefficients[kResidualMean]},
                                    {"velocity_sign_step", 2 * s.coefficients[kVelocitySign]},
                                    {"viscous_slope", s.coefficients[kVelocity]},
                                    {"acceleration_slope", s.coefficients[kAcceleration]},
                                    {"position_slope", s.coefficients[kPosition]},
                                    {"torque_slope", s.alone[kTorque]},
                                    {"correlations", correlations},
                                    {"explained", s.explained}};
  }
  return {{"worst_windows", windows}, {"joints", joints}};
}

JointDiagnosisContext MakeJointDiagnosisContext(const RobotDynamics& model, const JointDiagnosis& diagnosis,
                                                const std::string& validation_source, double min_explained) {
  JointDiagnosisContext c;
  c.model = &model;
  c.diagnosis = &diagnosis;
  c.validation_source = validation_source;
  c.min_explained = min_explained;
  return c;
}

std::string CandidateExplanation(const JointDiagnosisContext& c, const CandidateResult& r) {
  if (r.spec.kind == EffectKind::kPayload) {
    const InertialParams p = InertialParams::FromVector(Eigen::Map<const Vector10>(r.values.data()));
    const Eigen::Vector3d moments = Eigen::SelfAdjointEigenSolver<Matrix3>(p.rotational_inertia_about_com()).eigenvalues();
    const std::string pm = r.payload_std && std::isfinite(r.payload_std->mass) ? " +- " + F(r.payload_std->mass) : "";
    return r.link + " carries more than its URDF says: a payload of " + F(p.mass()) + pm + " kg, principal moments " +
           Vec3(moments) + " kg m^2 about its centre of mass at " +
           Vec3(p.com()) + " m (in the frame of " + r.link +
           "'s rigid body) explains the error (or the URDF inertia of that body is wrong)";
  }
  const int k = DofIndex(*c.model, r.joint);
  const JointResidualSignature* s = k >= 0 ? &c.diagnosis->held_out.residuals.joints[k] : nullptr;
  auto coefficient = [&](ResidualSignal signal) { return s != nullptr ? std::abs(s->alone[signal]) : 0.0; };
  const std::string j = r.joint;
  switch (r.spec.kind) {
    case EffectKind::kCoulomb:
      return "the " + j + " residual steps by " + F(2.0 * coefficient(kVelocitySign)) +
             " N m where the velocity changes sign: Coulomb (dry) friction of " + F(r.values[0]) + " N m is missing";
    case EffectKind::kViscous:
      return "the " + j + " residual grows in proportion to velocity (" + F(coefficient(kVelocity)) +
             " N m s/rad): viscous friction b = " + F(r.values[0]) + " N m s/rad is missing";
    case EffectKind::kOffset:
      return "the " + j + " residual has a constant part of " + F(coefficient(kResidualMean)) +
             " N m: a torque-sensor offset (zero-torque calibration) of " + F(r.values[0]) + " N m is missing";
    case EffectKind::kArmature:
      return "the " + j + " residual follows the acceleration (" + F(coefficient(kAcceleration)) +
             " kg m^2): reflected rotor inertia (armature) Ia = " + F(r.values[0]) + " kg m^2 is missing";
    case EffectKind::kSpring:
      return "the " + j + " residual grows with position (" + F(coefficient(kPosition)) + " N m/rad): a spring k = " +
             F(r.values[0]) + " N m/rad about q0 = " + F(r.values.size() > 1 ? r.values[1] : 0.0) +
             " rad (cable, hose, gravity compensator) is missing";
    case EffectKind::kAsymmetric:
      return "the " + j + " residual steps by different amounts in the two directions: dry friction of " +
             F(r.values[0]) + " N m for positive velocity and " + F(r.values.size() > 1 ? r.values[1] : 0.0) +
             " N m for negative (over " + F(r.spec.velocity_scale) + " rad/s) is missing" +
             (r.replaces.empty() ? "" : ", in place of " + r.replaces);
    case EffectKind::kSigmoid:
      return "the " + j + " residual rises like a sigmoid of the velocity (steepness " + F(r.spec.steepness) +
             " s/rad, shifted by " + F(r.spec.shift) + " rad/s, as Gaz et al. found on the Franka Panda): friction of amplitude " +
             F(r.values[0]) + " N m is missing" + (r.replaces.empty() ? "" : ", in place of " + r.replaces);
    default: return r.name;
  }
}

namespace {

// The fit, the held-out errors, the links' plausibility and where the model fails.
void FitSection(std::ostringstream& out, const JointDiagnosisContext& c) {
  const RobotDynamics& model = *c.model;
  const JointDiagnosis& d = *c.diagnosis;
  out << "Diagnosis: links";
  for (const EffectSpec& e : d.effects) out << " + " << e.text;
  out << " (" << model.num_parameters() << " parameters), fitted on " << d.train_samples << " samples, judged on "
      << d.validation_samples << " held-out samples (" << c.validation_source << ")";
  const bool held = std::find(d.frozen_bodies.begin(), d.frozen_bodies.end(), true) != d.frozen_bodies.end();
  out << (held ? "; links held at the URDF" : "") << "\n";
  out << "  fit: " << d.fit.lm.iterations << " iterations, " << (d.fit.lm.converged() ? "converged" : "NOT converged")
      << "; diagnosis " << FormatFixed(d.seconds, 2) << " s\n\n";
  out << "Held-out torque error, RMS (relative): URDF prior -> fitted model\n";
  ErrorTable(out, model.dof_names(), d.prior_validation, d.fit_validation, "N m");
  if (d.links_only_validation) {
    out << "\nWhat the effects bring, held-out RMS: links only -> links";
    for (const EffectSpec& e : d.effects) out << " + " << e.text;
    out << "\n";
    ErrorTable(out, model.dof_names(), *d.links_only_validation, d.fit_validation, "N m");
  }
  out << "\n" << PlausibilityText(model, d);
  out << "\n" << RunErrorsText(c.run_names, c.runs, "The fitted model's held-out error");
  out << "\n" << WhereItFailsText(model.dof_names(), d.held_out.residuals, "held-out residual of the fitted model");
}

// The missing effects: the suggestions with their evidence, then the next best not suggested.
void MissingEffectsSection(std::ostringstream& out, const JointDiagnosisContext& c) {
  const RobotDynamics& model = *c.model;
  const JointDiagnosis& d = *c.diagnosis;
  out << "\nMissing effects. Suggested when the held-out data support them (removing " << Percent(c.min_explained)
      << " of the held-out mean-square error, or a significant fall of it counted in independent samples) or when they "
         "restore the plausibility of links the model bends; ranked by the held-out share they remove (score, %), "
         "then by the share of plausibility they restore, near-ties to the simpler effect\n";
  const std::vector<std::string> bent = BentLinks(d);
  if (d.num_suggestions == 0 && !d.fit.lm.converged()) {
    out << "  No suggestion: the model's own fit did not converge (see the note below).\n";
  } else if (d.num_suggestions == 0) {
    out << "  No missing effect found: no candidate is supported by the held-out data or restores the links' "
           "plausibility";
    if (!d.candidates.empty()) {
      out << "; best: " << d.candidates[0].name << ", " << CandidateNotSuggested(d, d.candidates[0], c.min_explained, c.min_gain);
    }
    if (bent.empty()) {
      out << ". The model explains these data as well as any effect of the catalog would, with believable links.\n";
    } else {
      out << ". But links bend beyond the tolerance (see above): the model lacks something the catalog does not "
             "hold, or the URDF of those links is wrong.\n";
    }
  }
  constexpr int kShownSuggestions = 8;
  for (int i = 0; i < std::min(d.num_suggestions, kShownSuggestions); ++i) {
    const CandidateResult& r = d.candidates[i];
    out << "  " << i + 1 << ". " << EffectItem(r.spec) << " (score " << ScoreText(r.evidence) << "): " << Evidence(r.evidence)
        << "; held-out RMS " << F(d.fit_validation.total_rms, 4) << " -> " << F(r.validation.total_rms, 4)
        << " N m";
    const int k = DofIndex(model, r.joint);
    if (k >= 0) {
      out << " (" << r.joint << " " << F(d.fit_validation.rms[k], 4) << " -> " << F(r.validation.rms[k], 4)
          << ")";
    }
    if (r.implausibility != d.implausibility) {
      out << "; links' implausibility " << F(d.implausibility, 3) << " -> " << F(r.implausibility, 3);
    }
    out << "\n     " << CandidateExplanation(c, r) << "\n";
  }
  if (d.num_suggestions > kShownSuggestions) {
    out << "  ... and " << d.num_suggestions - kShownSuggestions << " more suggestions (see --json or --report)\n";
  }
  const int shown = std::min<int>(static_cast<int>(d.candidates.size()), d.num_suggestions + 3);
  if (shown > d.num_suggestions) {
    out << "  not suggested (next best):\n";
    for (int i = d.num_suggestions; i < shown; ++i) {
      out << "    " << d.candidates[i].name << " (score " << ScoreText(d.candidates[i].evidence) << "): "
          << CandidateNotSuggested(d, d.candidates[i], c.min_explained, c.min_gain) << "\n";
    }
  }
}

// The notes, what to do next, and whether every body is consistent.
void ClosingSection(std::ostringstream& out, const JointDiagnosisContext& c) {
  const RobotDynamics& model = *c.model;
  const JointDiagnosis& d = *c.diagnosis;
  for (const std::string& note : d.notes) out << "  note: " << note << "\n";
  if (d.num_suggestions > 0) {
    out << "\nNext: add the top suggestion (--effects ";
    bool first = true;
    for (const EffectSpec& e : EffectsWithCandidate(d.effects, model.dof_names(), d.candidates[0])) {
      out << (first ? "" : ",") << (e.inertia ? e.text : EffectItem(e));
      first = false;
    }
    out << ") and run again: what it explained leaves the ranking, what remains is ranked anew.\n";
  }
  bool consistent = true;
  BodiesJson(model, d.fit.x, &consistent);
  out << "\n"
      << (consistent ? "Every identified body is physically consistent."
                     : "SOME IDENTIFIED BODY IS NOT PHYSICALLY CONSISTENT (a bug: please report).")
      << "\n";
}

}  // namespace

std::string JointDiagnosisText(const JointDiagnosisContext& c) {
  std::ostringstream out;
  FitSection(out, c);
  MissingEffectsSection(out, c);
  ClosingSection(out, c);
  return out.str();
}

nlohmann::json JointDiagnosisJson(const JointDiagnosisContext& c) {
  const RobotDynamics& model = *c.model;
  const JointDiagnosis& d = *c.diagnosis;
  nlohmann::json j;
  j["samples"] = {{"train", d.train_samples}, {"validation", d.validation_samples}};
  j["validation_source"] = c.validation_source;
  j["rms_validation"] = PerJointJson(model, d.fit_validation.rms, d.fit_validation.total_rms);
  j["relative_rms_validation"] = PerJointJson(model, d.fit_validation.relative_rms, d.fit_validation.total_relative_rms);
  j["rms_prior"] = PerJointJson(model, d.prior_validation.rms, d.prior_validation.total_rms);
  if (d.links_only_validation) {
    j["rms_links_only"] = PerJointJson(model, d.links_only_validation->rms, d.links_only_validation->total_rms);
  }
  j["rms_train"] = PerJointJson(model, d.fit_train.rms, d.fit_train.total_rms);
  j["effects"] = EffectsJson(model, d.fit.x);
  // The diagnosed model's effects as --effects takes them (after --iterate: the loop's choice).
  std::string items;
  for (const EffectSpec& e : d.effects) items += (items.empty() ? "" : ",") + (e.inertia ? e.text : EffectItem(e));
  j["model_effects"] = items;
  bool consistent = true;
  j["bodies"] = BodiesJson(model, d.fit.x, &consistent);
  j["physically_consistent"] = consistent;
  j["iterations"] = d.fit.lm.iterations;
  j["converged"] = d.fit.lm.converged();
  j["links_held_at_urdf"] = std::find(d.frozen_bodies.begin(), d.frozen_bodies.end(), true) != d.frozen_bodies.end();
  nlohmann::json suggestions = nlohmann::json::array(), candidates = nlohmann::json::array();
  for (int i = 0; i < static_cast<int>(d.candidates.size()); ++i) {
    const CandidateResult& r = d.candidates[i];
    nlohmann::json s;
    s["effect"] = std::string(ToString(r.spec.kind));
    if (!r.joint.empty()) s["joint"] = r.joint;
    if (!r.link.empty()) s["link"] = r.link;
    s["name"] = r.name;
    s["item"] = EffectItem(r.spec);
    if (!r.replaces.empty()) s["replaces"] = r.replaces;
    s["rms_validation_after"] = PerJointJson(model, r.validation.rms, r.validation.total_rms);
    s["explained"] = r.explained;
    s["explanation"] = i < d.num_suggestions ? CandidateExplanation(c, r)
                                             : CandidateNotSuggested(d, r, c.min_explained, c.min_gain);
    s["score"] = r.evidence.score;
    s["evidence"] = {{"explained", r.evidence.explained},         {"significance", r.evidence.significance},
                     {"threshold", r.evidence.threshold},         {"restored", r.evidence.restored},
                     {"by_size", r.evidence.by_size},             {"by_significance", r.evidence.by_significance},
                     {"by_plausibility", r.evidence.by_plausibility}};
    s["implausibility_after"] = r.implausibility;
    if (!r.alternative_to.empty()) s["alternative_to"] = r.alternative_to;
    s["values"] = r.values;
    s["converged"] = r.converged;
    s["suggested"] = i < d.num_suggestions;
    if (i < d.num_suggestions) suggestions.push_back(s);
    candidates.push_back(s);
  }
  j["suggestions"] = suggestions;
  j["candidates"] = candidates;
  j["min_explained"] = c.min_explained;
  j["plausibility"] = PlausibilityJson(model, d);
  j["prior_tolerance"] = d.prior_tolerance;
  j["implausibility"] = d.implausibility;
  j["bent_links"] = BentLinks(d);
  j["validation_retraces_training"] = d.retraced;
  if (!d.stop_reason.empty()) j["stop_reason"] = d.stop_reason;
  j["notes"] = d.notes;
  j["seconds"] = d.seconds;
  j["where_it_fails"] = WhereItFailsJson(model.dof_names(), d.held_out.residuals);
  if (c.runs.size() > 1) j["runs"] = RunErrorsJson(c.run_names, c.runs);
  return j;
}

std::string DiagnosisPathText(const std::vector<DiagnosisStep>& path, const JointDiagnosis& final_diagnosis) {
  auto names = [](const std::vector<std::string>& v) {
    std::string s;
    for (size_t i = 0; i < v.size(); ++i) s += (i > 0 ? ", " : "") + v[i];
    return v.empty() ? std::string("none") : s;
  };
  std::ostringstream out;
  out << "Effects added in turn (the top suggestion each time):\n";
  if (path.empty()) out << "  none: nothing was suggested\n";
  for (size_t i = 0; i < path.size(); ++i) {
    const DiagnosisStep& s = path[i];
    out << "  " << i + 1 << ". added " << s.item << (s.replaced.empty() ? "" : " in place of " + s.replaced) << " (" << Evidence(s.evidence) << ")\n"
        << "     held-out RMS " << F(s.before.total_rms, 4) << " (" << Percent(s.before.total_relative_rms)
        << ") -> " << F(s.after.total_rms, 4) << " (" << Percent(s.after.total_relative_rms) << ") N m\n"
        << "     links' implausibility " << F(s.implausibility_before, 3) << " -> "
        << F(s.implausibility_after, 3) << "; bent links: " << names(s.bent_before) << " -> "
        << names(s.bent_after) << "\n";
  }
  out << "  stopped: "
      << (final_diagnosis.stop_reason.empty() ? std::string("nothing more is suggested") : final_diagnosis.stop_reason)
      << "\n";
  return out.str();
}

nlohmann::json DiagnosisPathJson(const RobotDynamics& model, const std::vector<DiagnosisStep>& path) {
  nlohmann::json j = nlohmann::json::array();
  for (const DiagnosisStep& s : path) {
    j.push_back({{"added", s.added},
                 {"item", s.item},
                 {"replaced", s.replaced},
                 {"explained", s.explained},
                 {"significance", s.evidence.significance},
                 {"restored", s.evidence.restored},
                 {"rms_validation_before", PerJointJson(model, s.before.rms, s.before.total_rms)},
                 {"rms_validation_after", PerJointJson(model, s.after.rms, s.after.total_rms)},
                 {"implausibility_before", s.implausibility_before},
                 {"implausibility_after", s.implausibility_after},
                 {"bent_links_before", s.bent_before},
                 {"bent_links_after", s.bent_after}});
  }
  return j;
}

void WriteJointDiagnosisReport(const std::string& directory, const JointDiagnosisContext& c, const std::string& text) {
  const RobotDynamics& model = *c.model;
  const JointDiagnosis& d = *c.diagnosis;
  DiagnosisPlotData p;
  p.title = "inertial diagnose";
  p.channels = model.dof_names();
  p.unit = "N m";
  p.velocity_label = "joint velocity [rad/s]";
  const ModelComparison& held_out = d.held_out;
  p.t = held_out.signals.t;
  p.measured = held_out.signals.tau;
  p.predicted = held_out.predicted;
  p.velocity = held_out.signals.qd;
  p.error_labels.push_back("URDF prior");
  p.error_rms.push_back(d.prior_validation.rms);
  if (d.links_only_validation) {
    p.error_labels.push_back("links only");
    p.error_rms.push_back(d.links_only_validation->rms);
  }
  std::string label = "fitted model";
  for (const EffectSpec& e : d.effects) label += " + " + e.text;
  p.error_labels.push_back(label);
  p.error_rms.push_back(d.fit_validation.rms);
  for (int i = 0; i < std::min(3, d.num_suggestions); ++i) {
    p.error_labels.push_back("+ " + d.candidates[i].name);
    p.error_rms.push_back(d.candidates[i].validation.rms);
  }
  for (const ResidualWindow& w : held_out.residuals.worst_windows) p.marked_windows.push_back({w.t_start, w.t_end});
  // The top suggestion's effect over the residual it explains (residual = model - measured, and the
  // measurement holds the effect: the residual follows minus the effect).
  if (d.num_suggestions > 0) {
    const CandidateResult& top = d.candidates[0];
    const int k = DofIndex(model, top.joint);
    if (k >= 0 && !top.values.empty() && std::isfinite(VelocityEffectTorque(top.spec, top.values, 0.0))) {
      constexpr int kPoints = 201;
      const int n = model.num_dofs();
      p.effect_velocity = Eigen::MatrixXd::Zero(kPoints, n);
      p.effect_residual = Eigen::MatrixXd::Constant(kPoints, n, std::nan(""));
      const double lo = held_out.signals.qd.col(k).minCoeff(), hi = held_out.signals.qd.col(k).maxCoeff();
      for (int i = 0; i < kPoints; ++i) {
        const double v = lo + (hi - lo) * i / (kPoints - 1);
        const double effect = VelocityEffectTorque(top.spec, top.values, v);
        p.effect_velocity(i, k) = v;
        p.effect_residual(i, k) = -effect;
      }
      p.effect_label = "- " + top.name + " (fitted)";
    }
  }
  std::vector<DiagnosisTableRow> rows;
  for (int i = 0; i < static_cast<int>(d.candidates.size()); ++i) {
    const CandidateResult& r = d.candidates[i];
    rows.push_back({std::string(ToString(r.spec.kind)), r.joint.empty() ? r.link : r.joint, r.evidence.score, r.explained,
                    r.validation.total_rms, i < d.num_suggestions,
                    i < d.num_suggestions ? CandidateExplanation(c, r) + " [" + Evidence(r.evidence) + "]"
                                          : CandidateNotSuggested(d, r, c.min_explained, c.min_gain)});
  }
  std::vector<std::string> summary{
      "Held-out RMS torque error: URDF prior " + F(d.prior_validation.total_rms, 4) + " N m, fitted model " +
          F(d.fit_validation.total_rms, 4) + " N m (" + std::to_string(d.validation_samples) + " samples, " +
          c.validation_source + ").",
      d.num_suggestions == 0 ? std::string("No missing effect found: no candidate is supported by the held-out data.")
                             : "Top suggestion: " + d.candidates[0].name + " (" + CandidateExplanation(c, d.candidates[0]) +
                                   "); held-out RMS with it " + F(d.candidates[0].validation.total_rms, 4) +
                                   " N m."};
  WriteDiagnosisHtml(directory, p, summary, rows, text);
}

std::string BodyCandidateExplanation(const BodyCandidateResult& r) {
  const Eigen::VectorXd& v = r.values;
  switch (r.kind) {
    case BodyEffectKind::kForceBias:
      return "a constant force of " + Vec3(v) + " N on the sensor reading (offset, cable drag) is missing";
    case BodyEffectKind::kMomentBias:
      return "a constant moment of " + Vec3(v) + " N m on the sensor reading is missing";
    case BodyEffectKind::kVelocityBias:
      return "the measured twist is biased by [" + F(v[0]) + ", " + F(v[1]) + ", " + F(v[2]) + "] rad/s, [" + F(v[3]) +
             ", " + F(v[4]) + ", " + F(v[5]) + "] m/s (an uncalibrated gyro or velocity estimate)";
    case BodyEffectKind::kGravity:
      return "gravity (or a constant acceleration of the frame) of " + Vec3(v) +
             " m/s^2 in the body frame is missing from the model";
  }
  return "";
}

std::string BodyDiagnosisText(const BodyDiagnosisContext& c) {
  const BodyDiagnosis& d = *c.diagnosis;
  const BodyEffectModel model(c.prior, d.effects);
  std::ostringstream out;
  out << "Diagnosis: single body";
  for (BodyEffectKind e : d.effects) out << " + " << ToString(e);
  out << ", fitted on " << d.train_pairs << " sample pairs (eq. 13), judged on " << d.validation_pairs
      << " held-out pairs (" << c.validation_source << ")\n  fit: " << d.fit.lm.iterations << " iterations, "
      << (d.fit.lm.converged() ? "converged" : "NOT converged") << "; diagnosis " << FormatFixed(d.seconds, 2) << " s\n";
  const InertialParams body = model.Body(d.fit.x);
  const ConsistencyReport cr = CheckConsistency(body);
  out << "  body: mass " << F(body.mass(), 5) << " kg, COM " << Vec3(body.com()) << " m, "
      << (cr.fully_consistent() ? "physically consistent" : "NOT physically consistent") << "\n";
  for (size_t k = 0; k < d.effects.size(); ++k) {
    out << "  " << ToString(d.effects[k]) << ":";
    const Eigen::VectorXd v = model.EffectValues(static_cast<int>(k), d.fit.x);
    for (int i = 0; i < v.size(); ++i) out << " " << F(v[i], 4);
    out << "\n";
  }
  const std::vector<std::string> names(std::begin(kWrenchChannels), std::end(kWrenchChannels));
  out << "\nHeld-out wrench error, RMS (relative): prior -> fitted model\n";
  ErrorTable(out, names, d.prior_validation, d.fit_validation, "N m or N");
  out << "\nMissing effects, ranked by the share of the held-out mean-square error they remove (suggested from "
      << Percent(c.min_explained) << " with a gain of at least p ln(rows) independent samples, or when significant)\n";
  if (d.num_suggestions == 0) {
    out << (d.fit.lm.converged() ? "  No missing effect found: no candidate is supported by the held-out data.\n"
                                 : "  No suggestion: the model's own fit did not converge (raise --max-iterations).\n");
  }
  for (int i = 0; i < static_cast<int>(d.candidates.size()); ++i) {
    const BodyCandidateResult& r = d.candidates[i];
    out << "  " << (i < d.num_suggestions ? std::to_string(i + 1) + ". " : "(not suggested) ") << ToString(r.kind)
        << " (score " << ScoreText(r.evidence) << "): explains " << Percent(r.explained) << ", significance "
        << F(r.evidence.significance, 3) << "; held-out RMS " << F(d.fit_validation.total_rms, 4) << " -> "
        << F(r.validation.total_rms, 4) << "\n";
    out << "     "
        << (i < d.num_suggestions ? BodyCandidateExplanation(r)
                                  : WhyNot(r.evidence, d.fit_validation, r.validation, c.min_explained, c.min_gain, false))
        << "\n";
  }
  return out.str();
}

nlohmann::json BodyDiagnosisJson(const BodyDiagnosisContext& c) {
  const BodyDiagnosis& d = *c.diagnosis;
  const BodyEffectModel model(c.prior, d.effects);
  nlohmann::json j;
  j["samples"] = {{"train_pairs", d.train_pairs}, {"validation_pairs", d.validation_pairs}};
  j["validation_source"] = c.validation_source;
  j["rms_validation"] = Channels(d.fit_validation.rms, d.fit_validation.total_rms);
  j["relative_rms_validation"] = Channels(d.fit_validation.relative_rms, d.fit_validation.total_relative_rms);
  j["rms_prior"] = Channels(d.prior_validation.rms, d.prior_validation.total_rms);
  j["rms_train"] = Channels(d.fit_train.rms, d.fit_train.total_rms);
  nlohmann::json effects = nlohmann::json::array();
  for (size_t k = 0; k < d.effects.size(); ++k) {
    const Eigen::VectorXd v = model.EffectValues(static_cast<int>(k), d.fit.x);
    effects.push_back({{"effect", std::string(ToString(d.effects[k]))},
                       {"values", std::vector<double>(v.data(), v.data() + v.size())}});
  }
  j["effects"] = effects;
  const InertialParams body = model.Body(d.fit.x);
  const ConsistencyReport cr = CheckConsistency(body);
  const Vector10 pi = body.vector();
  j["body"] = {{"mass", body.mass()},
               {"com", {body.com()[0], body.com()[1], body.com()[2]}},
               {"pi", std::vector<double>(pi.data(), pi.data() + 10)},
               {"theta", std::vector<double>(d.fit.x.data(), d.fit.x.data() + 10)},
               {"physically_consistent", cr.fully_consistent()}};
  j["physically_consistent"] = cr.fully_consistent();
  j["left_out"] = c.left_out;
  j["iterations"] = d.fit.lm.iterations;
  j["converged"] = d.fit.lm.converged();
  nlohmann::json suggestions = nlohmann::json::array(), candidates = nlohmann::json::array();
  for (int i = 0; i < static_cast<int>(d.candidates.size()); ++i) {
    const BodyCandidateResult& r = d.candidates[i];
    nlohmann::json s = {{"effect", std::string(ToString(r.kind))},
                        {"target", "body"},
                        {"rms_validation_after", Channels(r.validation.rms, r.validation.total_rms)},
                        {"explained", r.explained},
                        {"explanation", i < d.num_suggestions
                                            ? BodyCandidateExplanation(r)
                                            : WhyNot(r.evidence, d.fit_validation, r.validation, c.min_explained,
                                                     c.min_gain, false)},
                        {"score", r.evidence.score},
                        {"significance", r.evidence.significance},
                        {"threshold", r.evidence.threshold},
                        {"values", std::vector<double>(r.values.data(), r.values.data() + r.values.size())},
                        {"converged", r.converged},
                        {"suggested", i < d.num_suggestions}};
    if (i < d.num_suggestions) suggestions.push_back(s);
    candidates.push_back(s);
  }
  j["suggestions"] = suggestions;
  j["candidates"] = candidates;
  j["min_explained"] = c.min_explained;
  j["folds"] = d.folds;
  nlohmann::json tau = nlohmann::json::object();
  for (int k = 0; k < 6 && k < d.residual_tau.size(); ++k) tau[kWrenchChannels[k]] = d.residual_tau[k];
  j["residual_correlation_time"] = tau;
  j["seconds"] = d.seconds;
  return j;
}

void WriteBodyDiagnosisReport(const std::string& directory, const BodyDiagnosisContext& c, const std::string& text) {
  const BodyDiagnosis& d = *c.diagnosis;
  const BodyEffectModel model(c.prior, d.effects);
  const BodyLog& log = *c.validation;
  const int P = log.num_pairs();
  DiagnosisPlotData p;
  p.title = "inertial diagnose (single body)";
  p.channels.assign(std::begin(kWrenchChannels), std::end(kWrenchChannels));
  p.unit = "N m | N";
  p.velocity_label = "matching twist component (wx..wz, vx..vz) [rad/s | m/s]";
  p.t.resize(P);
  p.measured.resize(P, 6);
  p.velocity.resize(P, 6);
  for (int i = 0; i < P; ++i) {
    p.t[i] = 0.5 * (log.samples[i].t + log.samples[i + 1].t);
    p.measured.row(i) = BodyEffectModel::MeasuredPair(log, i).transpose();
    p.velocity.row(i) = (0.5 * (log.samples[i].twist + log.samples[i + 1].twist)).transpose();
  }
  p.predicted = model.Residuals(d.fit.x, log) + p.measured;
  p.error_labels = {"prior", "fitted model"};
  p.error_rms = {d.prior_validation.rms, d.fit_validation.rms};
  for (int i = 0; i < d.num_suggestions; ++i) {
    p.error_labels.push_back("+ " + std::string(ToString(d.candidates[i].kind)));
    p.error_rms.push_back(d.candidates[i].validation.rms);
  }
  std::vector<DiagnosisTableRow> rows;
  for (int i = 0; i < static_cast<int>(d.candidates.size()); ++i) {
    const BodyCandidateResult& r = d.candidates[i];
    rows.push_back({std::string(ToString(r.kind)), "body", r.evidence.score, r.explained, r.validation.total_rms, i < d.num_suggestions,
                    i < d.num_suggestions ? BodyCandidateExplanation(r)
                                          : WhyNot(r.evidence, d.fit_validation, r.validation, c.min_explained,
                                                   c.min_gain, false)});
  }
  std::vector<std::string> summary{"Held-out RMS wrench error: prior " + F(d.prior_validation.total_rms, 4) +
                                   ", fitted model " + F(d.fit_validation.total_rms, 4) + " (" +
                                   c.validation_source + ")."};
  WriteDiagnosisHtml(directory, p, summary, rows, text);
}

}  // namespace inertial
