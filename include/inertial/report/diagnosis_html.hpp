/// @file diagnosis_html.hpp
/// The --report page of `inertial diagnose`: one self-contained HTML file (figures embedded as
/// base64 PNG, no external resource) that a person opens in a browser, plus the figures' data and
/// gnuplot scripts beside it. Figures, drawn by gnuplot (pngcairo), on the held-out data:
///   torques.png            measured and model output per channel against time
///   residual_time.png      residual (model - measured) per channel against time
///   residual_velocity.png  residual against the channel's velocity (the friction signature: a
///                          step at zero velocity is Coulomb friction, a slope viscous friction),
///                          with the top suggestion's fitted effect drawn over the residual it explains
/// The worst windows are shaded on the time plots; every axis spans its data (no empty margins).
///   errors.png             held-out RMS per channel before and after each effect
/// and the ranked table of candidate effects with their explanations.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

namespace inertial {

struct DiagnosisPlotData {
  std::string title;
  std::vector<std::string> channels;  ///< joint names, or wrench components
  std::string unit;                   ///< of measured/predicted, e.g. "N m"
  std::string velocity_label;         ///< x label of the residual-vs-velocity figure
  Eigen::VectorXd t;                  ///< held-out sample times [s]
  Eigen::MatrixXd measured, predicted, velocity;  ///< rows = samples, columns = channels
  /// Bars of the before/after figure: a label ("URDF prior", "fitted model", "+ coulomb@knee") and
  /// the held-out RMS per channel for each.
  std::vector<std::string> error_labels;
  std::vector<Eigen::VectorXd> error_rms;
  /// Time windows [t_start, t_end] shaded on the time plots (the worst windows).
  std::vector<std::pair<double, double>> marked_windows;
  /// Optional curve over residual_velocity.png: at velocities effect_velocity (per channel column),
  /// the residual the fitted effect explains (NaN: none on that channel), labelled effect_label.
  Eigen::MatrixXd effect_velocity, effect_residual;
  std::string effect_label;
};

struct DiagnosisTableRow {
  std::string effect, target;
  double score = 0.0;       ///< the ranking's score (candidate_evidence.hpp), shown as a percentage
  double explained = 0.0;   ///< share of the held-out mean-square error removed
  double rms_after = 0.0;   ///< held-out RMS, all channels, with the effect
  bool suggested = false;
  std::string explanation;
};

/// Writes DIR/index.html and the figures (creates DIR if needed). `summary` lines go on top (plain
/// text, escaped), `text_report` in a preformatted block at the end.
/// @throws std::runtime_error naming the file or command that failed, std::invalid_argument on
/// inconsistent sizes.
void WriteDiagnosisHtml(const std::string& directory, const DiagnosisPlotData& data,
                        const std::vector<std::string>& summary, const std::vector<DiagnosisTableRow>& rows,
                        const std::string& text_report);

/// The names of the files WriteDiagnosisHtml writes into its directory (index.html, the figures,
/// their data and gnuplot scripts), e.g. to refuse a directory that holds an input under one of them.
const std::vector<std::string>& DiagnosisReportFileNames();

/// RFC 4648 base64 of bytes (for data: URIs).
std::string Base64(const std::string& bytes);

/// Text with &, <, >, " escaped for HTML.
std::string HtmlEscaped(const std::string& text);

}  // namespace inertial
