#include "inertial/report/diagnosis_html.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "inertial/formats/file_error.hpp"
#include "inertial/report/gnuplot.hpp"
#include "inertial/model/number_text.hpp"

namespace inertial {
namespace fs = std::filesystem;
namespace {

constexpr int kMaxPlottedSamples = 20000;  // a stride keeps larger logs quick to draw

void WriteFile(const fs::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  if (!out) throw std::runtime_error(CannotText("write", "", path.string()));
}

std::string ReadBinary(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(CannotText("read", "", path.string()));
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// A zero is shown without its sign ("-0", "-0.0" in a table or a plot are noise).
std::string WithoutSignOfZero(const std::string& s) { return s == "-0.0" || s == "-0" ? s.substr(1) : s; }
// Significant digits (number_text.hpp).
std::string Number(double x, int significant_digits = 4) { return WithoutSignOfZero(FormatNumber(x, significant_digits)); }
std::string Fixed(double x, int decimals) { return WithoutSignOfZero(FormatFixed(x, decimals)); }

}  // namespace

std::string Base64(const std::string& bytes) {
  static const char* kAlphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3) {
    const unsigned v = (static_cast<unsigned char>(bytes[i]) << 16) | (static_cast<unsigned char>(bytes[i + 1]) << 8) |
                       static_cast<unsigned char>(bytes[i + 2]);
    for (int s = 18; s >= 0; s -= 6) out += kAlphabet[(v >> s) & 63];
  }
  const size_t rest = bytes.size() - i;
  if (rest > 0) {
    unsigned v = static_cast<unsigned char>(bytes[i]) << 16;
    if (rest == 2) v |= static_cast<unsigned char>(bytes[i + 1]) << 8;
    out += kAlphabet[(v >> 18) & 63];
    out += kAlphabet[(v >> 12) & 63];
    out += rest == 2 ? kAlphabet[(v >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

std::string HtmlEscaped(const std::string& text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

namespace {

// The sizes of everything plotted agree; std::invalid_argument otherwise.
void CheckPlotData(const DiagnosisPlotData& d) {
  const int n = static_cast<int>(d.channels.size()), N = static_cast<int>(d.t.size());
  if (n == 0 || N == 0 || d.measured.rows() != N || d.predicted.rows() != N || d.velocity.rows() != N ||
      d.measured.cols() != n || d.predicted.cols() != n || d.velocity.cols() != n ||
      d.error_labels.size() != d.error_rms.size()) {
    throw std::invalid_argument("diagnosis report: inconsistent data sizes");
  }
  for (const Eigen::VectorXd& e : d.error_rms) {
    if (e.size() != n) throw std::invalid_argument("diagnosis report: an error bar set has the wrong size");
  }
}

// The data files: heldout.dat (t, then per channel measured, predicted, residual, velocity),
// errors.dat (the RMS per channel of each error set) and, with an effect curve, effect.dat.
void WritePlotData(const fs::path& dir, const DiagnosisPlotData& d) {
  const int n = static_cast<int>(d.channels.size()), N = static_cast<int>(d.t.size());
  std::ostringstream out;
  out << "# t";
  for (const std::string& c : d.channels) out << " measured_" << c << " model_" << c << " residual_" << c << " velocity_" << c;
  out << "\n";
  const int stride = std::max(1, (N + kMaxPlottedSamples - 1) / kMaxPlottedSamples);
  for (int i = 0; i < N; i += stride) {
    out << Number(d.t[i], 9);
    for (int k = 0; k < n; ++k) {
      out << " " << Number(d.measured(i, k), 7) << " " << Number(d.predicted(i, k), 7) << " "
          << Number(d.predicted(i, k) - d.measured(i, k), 7) << " " << Number(d.velocity(i, k), 7);
    }
    out << "\n";
  }
  WriteFile(dir / "heldout.dat", out.str());
  std::ostringstream errors;
  errors << "# channel";
  for (const std::string& l : d.error_labels) errors << " \"" << l << "\"";
  errors << "\n";
  for (int k = 0; k < n; ++k) {
    errors << "\"" << d.channels[k] << "\"";
    for (const Eigen::VectorXd& e : d.error_rms) errors << " " << Number(e[k], 7);
    errors << "\n";
  }
  WriteFile(dir / "errors.dat", errors.str());
  if (d.effect_velocity.rows() > 0) {
    if (d.effect_velocity.cols() != n || d.effect_residual.rows() != d.effect_velocity.rows() ||
        d.effect_residual.cols() != n) {
      throw std::invalid_argument("diagnosis report: the effect curve has the wrong size");
    }
    std::ostringstream curve;
    curve << "# per channel: velocity, residual the fitted effect explains\n";
    for (Eigen::Index i = 0; i < d.effect_velocity.rows(); ++i) {
      for (int k = 0; k < n; ++k) {
        curve << (k ? " " : "") << Number(d.effect_velocity(i, k), 7) << " "
              << (std::isfinite(d.effect_residual(i, k)) ? Number(d.effect_residual(i, k), 7) : "NaN");
      }
      curve << "\n";
    }
    WriteFile(dir / "effect.dat", curve.str());
  }
}

// The start of a figure of one panel per channel (n panels, `height` pixels).
void BeginMultiplot(std::ostringstream& gp, int n, const std::string& png, const std::string& title) {
  const int height = std::max(300, 170 * n);
  gp << "set terminal pngcairo size 1200," << height << " font 'sans,10'\n"
     << "set output '" << png << "'\n"
     << "set multiplot layout " << n << ",1 title " << GnuplotQuoted(title) << "\n"
     << "set termoption noenhanced\n"  // names like lwr_0_joint and coulomb@knee are not markup
     << "set grid\nset key outside right top\nset lmargin 12\nset rmargin 22\n"
     // Axes span the data: x exactly, y with 5 % of room.
     << "set autoscale xfix\nset offsets 0, 0, graph 0.05, graph 0.05\n";
}

using Figure = std::pair<std::string, std::string>;  // file, caption

// torques.png: measured and model per channel, the worst windows shaded.
Figure TorquesFigure(const fs::path& dir, const DiagnosisPlotData& d, const std::string& shading) {
  const int n = static_cast<int>(d.channels.size());
  std::ostringstream gp;
  BeginMultiplot(gp, n, "torques.png", d.title + ": measured and model (held-out data; worst windows shaded)");
  gp << shading;
  for (int k = 0; k < n; ++k) {
    gp << "set ylabel " << GnuplotQuoted(d.channels[k] + " [" + d.unit + "]") << "\n"
       << (k == n - 1 ? "set xlabel 't [s]'\n" : "unset xlabel\n")
       << "plot 'heldout.dat' using 1:" << 2 + 4 * k << " with lines lw 1 lc rgb '#888888' title 'measured', "
       << "'' using 1:" << 3 + 4 * k << " with lines lw 1.5 lc rgb '#c03020' title 'model'\n";
  }
  gp << "unset multiplot\n";
  WriteFile(dir / "torques.gp", gp.str());
  return {"torques.png", "Measured and model output per channel on the held-out data."};

}

// residual_time.png: the residual against time, the worst windows shaded.
Figure ResidualTimeFigure(const fs::path& dir, const DiagnosisPlotData& d, const std::string& shading) {
  const int n = static_cast<int>(d.channels.size());
  std::ostringstream gp;
  BeginMultiplot(gp, n, "residual_time.png", d.title + ": residual (model - measured) against time (worst windows shaded)");
  gp << shading;
  for (int k = 0; k < n; ++k) {
    gp << "set ylabel " << GnuplotQuoted(d.channels[k] + " [" + d.unit + "]") << "\n"
       << (k == n - 1 ? "set xlabel 't [s]'\n" : "unset xlabel\n")
       << "plot 'heldout.dat' using 1:" << 4 + 4 * k << " with lines lw 1 lc rgb '#3060a0' title 'residual'\n";
  }
  gp << "unset multiplot\n";
  WriteFile(dir / "residual_time.gp", gp.str());
  return {"residual_time.png", "Residual against time: where the model fails."};

}

// residual_velocity.png: the residual against velocity, with the top suggestion's curve if any.
Figure ResidualVelocityFigure(const fs::path& dir, const DiagnosisPlotData& d) {
  const int n = static_cast<int>(d.channels.size());
  const bool curve = d.effect_velocity.rows() > 0;
  std::ostringstream gp;
  BeginMultiplot(gp, n, "residual_velocity.png", d.title + ": residual against velocity (friction signature)");
  for (int k = 0; k < n; ++k) {
    gp << "set ylabel " << GnuplotQuoted(d.channels[k] + " [" + d.unit + "]") << "\n"
       << "set xlabel " << GnuplotQuoted(d.velocity_label) << "\n"
       << "plot 'heldout.dat' using " << 5 + 4 * k << ":" << 4 + 4 * k
       << " with points pt 7 ps 0.25 lc rgb '#3060a0' title 'residual'";
    if (curve && std::isfinite(d.effect_residual.col(k).sum())) {
      gp << ", 'effect.dat' using " << 1 + 2 * k << ":" << 2 + 2 * k << " with lines lw 2.5 lc rgb '#d07000' title "
         << GnuplotQuoted(d.effect_label);
    }
    gp << "\n";
  }
  gp << "unset multiplot\n";
  WriteFile(dir / "residual_velocity.gp", gp.str());
  return {"residual_velocity.png",
                     "Residual against velocity: a step at zero velocity is Coulomb friction, a slope viscous "
                     "friction." +
                         std::string(curve ? " The orange curve is the top suggestion's fitted effect." : "")};

}

// errors.png: the held-out RMS per channel before and after each effect.
Figure ErrorsFigure(const fs::path& dir, const DiagnosisPlotData& d) {
  std::ostringstream gp;
  gp << "set terminal pngcairo size 1200,450 font 'sans,10'\nset output 'errors.png'\nset termoption noenhanced\n"
     << "set title " << GnuplotQuoted(d.title + ": held-out RMS error before and after each effect") << "\n"
     << "set style data histograms\nset style histogram clustered gap 1\nset style fill solid 0.8 border -1\n"
     << "set ylabel " << GnuplotQuoted("RMS [" + d.unit + "]") << "\nset grid ytics\nset key outside right top\n"
     << "set yrange [0:*]\n";
  gp << "plot ";
  for (size_t e = 0; e < d.error_labels.size(); ++e) {
    gp << (e ? ", " : "") << "'errors.dat' using " << e + 2 << (e == 0 ? ":xtic(1)" : "") << " title "
       << GnuplotQuoted(d.error_labels[e]);
  }
  gp << "\n";
  WriteFile(dir / "errors.gp", gp.str());
  return {"errors.png", "Held-out RMS per channel before and after each effect."};

}

// index.html: the summary, the ranking table, the figures inline and the text report.
std::string DiagnosisPage(const fs::path& dir, const DiagnosisPlotData& d, const std::vector<std::string>& summary,
                          const std::vector<DiagnosisTableRow>& rows, const std::vector<Figure>& figures,
                          const std::string& text_report) {
  std::ostringstream html;
  html << "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>" << HtmlEscaped(d.title)
       << "</title>\n<style>\nbody{font-family:sans-serif;max-width:1250px;margin:1em auto;padding:0 1em;color:#222}\n"
       << "table{border-collapse:collapse}td,th{border:1px solid #bbb;padding:3px 8px;text-align:left}\n"
       << "tr.suggested{background:#fff3d0}img{max-width:100%;border:1px solid #ddd}pre{background:#f6f6f6;padding:1em;"
       << "overflow-x:auto}\n</style>\n</head>\n<body>\n<h1>" << HtmlEscaped(d.title) << "</h1>\n";
  for (const std::string& line : summary) html << "<p>" << HtmlEscaped(line) << "</p>\n";
  html << "<h2>Candidate effects, ranked by score (suggestions first)</h2>\n";
  if (rows.empty()) {
    html << "<p>No candidate was tested.</p>\n";
  } else {
    html << "<table id=\"ranking\">\n<tr><th>rank</th><th>effect</th><th>on</th><th>score</th><th>explained</th><th>held-out RMS with it ["
         << HtmlEscaped(d.unit) << "]</th><th>suggested</th><th>explanation</th></tr>\n";
    for (size_t r = 0; r < rows.size(); ++r) {
      const DiagnosisTableRow& row = rows[r];
      html << "<tr" << (row.suggested ? " class=\"suggested\"" : "") << "><td>" << r + 1 << "</td><td>"
           << HtmlEscaped(row.effect) << "</td><td>" << HtmlEscaped(row.target) << "</td><td>"
           << Fixed(100.0 * row.score, 1) << "</td><td>" << Fixed(100.0 * row.explained, 1) << " %</td><td>" << Number(row.rms_after) << "</td><td>"
           << (row.suggested ? "yes" : "no") << "</td><td>" << HtmlEscaped(row.explanation) << "</td></tr>\n";
    }
    html << "</table>\n";
  }
  for (const auto& [png, caption] : figures) {
    html << "<h2>" << HtmlEscaped(caption) << "</h2>\n<img id=\"" << png.substr(0, png.size() - 4) << "\" alt=\""
         << HtmlEscaped(caption) << "\" src=\"data:image/png;base64," << Base64(ReadBinary(dir / png)) << "\">\n";
  }
  html << "<h2>Text report</h2>\n<pre>" << HtmlEscaped(text_report) << "</pre>\n</body>\n</html>\n";
  return html.str();
}

}  // namespace

void WriteDiagnosisHtml(const std::string& directory, const DiagnosisPlotData& d, const std::vector<std::string>& summary,
                        const std::vector<DiagnosisTableRow>& rows, const std::string& text_report) {
  CheckPlotData(d);
  const fs::path dir(directory);
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw std::runtime_error("cannot create '" + directory + "': " + ec.message());
  WritePlotData(dir, d);
  std::string shading;
  for (const auto& [t0, t1] : d.marked_windows) {
    shading += "set object rect from " + Number(t0, 9) + ", graph 0 to " + Number(t1, 9) +
               ", graph 1 behind fc rgb '#ffd8d0' fs solid 0.6 noborder\n";
  }
  const std::vector<Figure> figures = {TorquesFigure(dir, d, shading), ResidualTimeFigure(dir, d, shading),
                                       ResidualVelocityFigure(dir, d), ErrorsFigure(dir, d)};
  for (const auto& [png, caption] : figures) {
    const std::string script = png.substr(0, png.size() - 4) + ".gp";
    RunGnuplot(dir, script);
    if (!fs::exists(dir / png) || fs::file_size(dir / png) == 0) {
      throw std::runtime_error("gnuplot produced no '" + (dir / png).string() + "'");
    }
  }

  WriteFile(dir / "index.html", DiagnosisPage(dir, d, summary, rows, figures, text_report));
}

const std::vector<std::string>& DiagnosisReportFileNames() {
  static const std::vector<std::string> names = {
      "index.html",          "heldout.dat",       "errors.dat",        "torques.gp",   "torques.png",
      "residual_time.gp",    "residual_time.png", "residual_velocity.gp", "residual_velocity.png",
      "errors.gp",           "errors.png",        "effect.dat"};
  return names;
}

}  // namespace inertial
