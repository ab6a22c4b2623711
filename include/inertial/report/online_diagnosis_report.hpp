/// @file online_diagnosis_report.hpp
/// What the online diagnosis (diagnosis/online_diagnosis.hpp) says, for people and scripts: the
/// ranked suggestions with their one-line explanations (inertiald's log at exit, replay --diagnose)
/// and JSON (replay --diagnose --json: `suggestions`, each with `effect` and `joint` or `link`, as
/// `inertial diagnose --json` has them). Units: N m, rad, s, kg, m.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "inertial/diagnosis/online_diagnosis.hpp"

namespace inertial {

/// One line in physical words, e.g. "the knee residual steps where the velocity changes sign:
/// Coulomb (dry) friction of 0.055 N m is missing".
std::string OnlineCandidateExplanation(const OnlineCandidate& candidate);

/// "Online diagnosis (prequential, last 20 s, 10000 samples): model RMS ... \n  1. coulomb@knee ...",
/// or that nothing is suggested, with the next best candidates and the bent links.
std::string OnlineDiagnosisText(const OnlineDiagnosisResult& result);

/// {"samples", "window_s", "rms", "relative_rms", "suggestions": [{"effect", "joint" | "link", "item",
/// "replaces", "explained", "significance", "threshold", "restored", "score", "evidence",
/// "rms_before", "rms_after", "values", "explanation"}], "candidates": [... the others, with
/// "alternative_to"], "bent_links", "implausibility", "notes"}.
nlohmann::json OnlineDiagnosisJson(const OnlineDiagnosisResult& result);

}  // namespace inertial
