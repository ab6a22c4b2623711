#include "inertial/report/study_report.hpp"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <stdexcept>

#include "inertial/formats/file_error.hpp"
#include "inertial/report/gnuplot.hpp"

namespace inertial {
namespace {

constexpr int kBins = kHistogramBins;  // + 1 "failed" bin

// Counts per bin (kBins iteration bins, then failures).
std::vector<int> Histogram(const StudyResult& result, int method) {
  std::vector<int> counts(kBins + 1, 0);
  for (const BodyOutcome& b : result.bodies) {
    const MethodOutcome& m = b.methods[method];
    if (m.failed) {
      ++counts[kBins];
    } else {
      const int width = HistogramBinWidth(result.options.solver.max_iterations);
      const int bin = std::min(kBins - 1, std::max(0, (m.iterations - 1) / width));
      ++counts[bin];
    }
  }
  return counts;
}

std::string Percent(int count, int total) {
  std::ostringstream os;
  os << std::fixed << std::setprecision(1) << 100.0 * count / total << " %";
  return os.str();
}

}  // namespace

std::string StudyTable(const StudyResult& result) {
  const StudySummary& s = result.summary;
  const StudyOptions& o = result.options;
  std::ostringstream os;
  os << "Rucker & Wensing 2022, Section VI: " << s.bodies << " random bodies (Table I), seed " << o.seed << "\n";
  os << "  wrench w_k = sin(t + k pi/3), t in [0, " << std::setprecision(4) << o.duration << "] s, samples every "
     << o.sample_interval << " s, velocity noise U[" << o.noise_bias - 0.5 * o.noise_width << ", "
     << o.noise_bias + 0.5 * o.noise_width << "], Dormand-Prince 5(4) rtol " << o.integrator.relative_tolerance
     << ", " << s.integrator_steps << " integrator steps\n\n";
  os << "Linear least squares on pi                      this run            paper (of 1000)\n";
  auto row = [&](const std::string& name, const std::string& ours, const std::string& paper) {
    os << "  " << std::left << std::setw(44) << name << std::setw(20) << ours << paper << "\n";
  };
  auto count = [&](int n) { return std::to_string(n) + " (" + Percent(n, s.bodies) + ")"; };
  auto num = [](double v) {
    std::ostringstream x;
    x << std::fixed << std::setprecision(3) << v;
    return x.str();
  };
  row("not physically consistent", count(s.nonphysical), "151 (15.1 %)");
  row("negative mass", std::to_string(s.negative_mass), "0");
  row("I (about origin) not positive definite", std::to_string(s.not_positive_definite), "42");
  row("  mean most negative eigenvalue [kg m^2]", num(s.mean_most_negative_eigenvalue), "-0.04");
  row("I (about COM) not positive definite", std::to_string(s.not_positive_definite_com), "-");
  row("triangle inequality violated (at COM)", std::to_string(s.triangle_violations), "151 (all nonphysical)");
  row("  mean triangle violation [kg m^2]", num(s.mean_triangle_violation), "-0.09");
  row("median parameter error |dpi|/|pi|", num(s.median_linear_ls_parameter_error), "-");
  const int cap = o.solver.max_iterations;
  const int width = HistogramBinWidth(cap);
  os << "\nLevenberg-Marquardt, at most " << cap << " iterations (paper: 50), started from the identity spatial inertia\n";
  os << "  " << std::left << std::setw(14) << "method" << std::right << std::setw(9) << "failures" << std::setw(11)
     << "median its" << std::setw(14) << "s/iteration" << std::setw(14) << "median |dpi|"
     << "   iterations histogram (1-" << width << ", " << width + 1 << "-" << 2 * width << ", ..., "
     << (kBins - 1) * width + 1 << "-" << kBins * width << " | failed)\n";
  for (int k = 0; k < kStudyMethods; ++k) {
    const MethodSummary& m = s.methods[k];
    os << "  " << std::left << std::setw(14) << StudyMethodName(k) << std::right << std::setw(9) << m.failures
       << std::setw(11) << std::setprecision(3) << m.median_iterations << std::setw(14) << std::scientific
       << std::setprecision(2) << m.seconds_per_iteration << std::setw(14) << m.median_parameter_error
       << std::defaultfloat << "   ";
    const std::vector<int> h = Histogram(result, k);
    for (int i = 0; i < kBins; ++i) os << std::setw(4) << h[i];
    os << " |" << std::setw(4) << h[kBins] << "\n";
  }
  os << "  paper: 0.02 s per iteration for every method (Matlab lsqnonlin); eigenvalue: wide spread of\n"
        "  iterations, few failures; exponential: fast, far more failures; log-Cholesky: fast, few failures.\n";
  os << "  failure = stopped at " << cap << " iterations or numerically, or (consistent methods) final parameters\n"
        "  outside the map's consistent domain (eigenvalue map: m or some L not positive).\n"
        "  near-degenerate (not failures): consistent by construction, margins below 1e-12 relative:";
  for (int k = 1; k < kStudyMethods; ++k) os << " " << StudyMethodName(k) << " " << s.methods[k].near_degenerate_results;
  os << "\n  suboptimal (cost > 0.1 % above the best consistent method on that body):";
  for (int k = 1; k < kStudyMethods; ++k) os << " " << StudyMethodName(k) << " " << s.methods[k].suboptimal_results;
  os << "\n";
  os << "\nwall time " << std::fixed << std::setprecision(2) << s.wall_seconds << " s\n";
  return os.str();
}

nlohmann::json StudyToJson(const StudyResult& result) {
  const StudySummary& s = result.summary;
  const StudyOptions& o = result.options;
  nlohmann::json j;
  j["bodies"] = s.bodies;
  j["seed"] = o.seed;
  j["settings"] = {{"duration_s", o.duration},
                   {"sample_interval_s", o.sample_interval},
                   {"noise_width", o.noise_width},
                   {"noise_bias", o.noise_bias},
                   {"integrator", "dormand_prince_5_4"},
                   {"integrator_relative_tolerance", o.integrator.relative_tolerance},
                   {"integrator_absolute_tolerance", o.integrator.absolute_tolerance},
                   {"integrator_steps", s.integrator_steps},
                   {"max_iterations", o.solver.max_iterations},
                   {"function_tolerance", o.solver.function_tolerance},
                   {"step_tolerance", o.solver.step_tolerance},
                   {"gradient_tolerance", o.solver.gradient_tolerance},
                   {"start", "identity spatial inertia"}};
  j["linear_ls"] = {{"nonphysical", s.nonphysical},
                    {"negative_mass", s.negative_mass},
                    {"not_positive_definite", s.not_positive_definite},
                    {"not_positive_definite_com", s.not_positive_definite_com},
                    {"triangle_violations", s.triangle_violations},
                    {"mean_most_negative_eigenvalue", s.mean_most_negative_eigenvalue},
                    {"mean_triangle_violation", s.mean_triangle_violation},
                    {"median_parameter_error", s.median_linear_ls_parameter_error}};
  nlohmann::json methods = nlohmann::json::object();
  for (int k = 0; k < kStudyMethods; ++k) {
    const MethodSummary& m = s.methods[k];
    nlohmann::json stops = nlohmann::json::object();
    for (const BodyOutcome& b : result.bodies) {
      const std::string reason(ToString(b.methods[k].reason));
      stops[reason] = stops.value(reason, 0) + 1;
    }
    methods[std::string(StudyMethodName(k))] = {{"iterations", m.iterations},
                                                {"failures", m.failures},
                                                {"max_iteration_stops", m.max_iteration_stops},
                                                {"numerical_failures", m.numerical_failures},
                                                {"inconsistent_results", m.inconsistent_results},
                                                {"near_degenerate_results", m.near_degenerate_results},
                                                {"suboptimal_results", m.suboptimal_results},
                                                {"stop_reasons", stops},
                                                {"seconds_per_iteration", m.seconds_per_iteration},
                                                {"median_iterations", m.median_iterations},
                                                {"median_parameter_error", m.median_parameter_error},
                                                {"mean_parameter_error", m.mean_parameter_error},
                                                {"histogram", Histogram(result, k)}};
  }
  j["methods"] = methods;
  {
    const int width = HistogramBinWidth(o.solver.max_iterations);
    j["histogram_bins"] = "iterations 1-" + std::to_string(width) + ", ..., " + std::to_string((kBins - 1) * width + 1) +
                          "-" + std::to_string(kBins * width) + ", then failed";
  }
  j["paper"] = {{"bodies", PaperStudyFigures::kBodies},
                {"nonphysical", PaperStudyFigures::kNonphysical},
                {"negative_mass", PaperStudyFigures::kNegativeMass},
                {"not_positive_definite", PaperStudyFigures::kNotPositiveDefinite},
                {"mean_most_negative_eigenvalue", PaperStudyFigures::kMeanMostNegativeEigenvalue},
                {"triangle_violations", PaperStudyFigures::kTriangleViolations},
                {"mean_triangle_violation", PaperStudyFigures::kMeanTriangleViolation},
                {"seconds_per_iteration", PaperStudyFigures::kSecondsPerIteration}};
  j["wall_seconds"] = s.wall_seconds;
  return j;
}

void WriteStudyReport(const StudyResult& result, const std::string& directory) {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::create_directories(directory, ec);
  if (ec) throw std::runtime_error("cannot create report directory '" + directory + "': " + ec.message());
  const fs::path dir(directory);
  auto write = [](const fs::path& path, const std::string& text) {
    std::ofstream out(path);
    out << text;
    out.close();
    if (!out) throw std::runtime_error(CannotText("write", "", path.string()));
  };
  write(dir / "study.json", StudyToJson(result).dump(2) + "\n");
  write(dir / "table.txt", StudyTable(result));

  std::ostringstream data;
  data << "# bin_label linear eigenvalue exponential log_cholesky (bodies per bin)\n";
  std::array<std::vector<int>, kStudyMethods> h;
  for (int k = 0; k < kStudyMethods; ++k) h[k] = Histogram(result, k);
  for (int i = 0; i <= kBins; ++i) {
    const int width = HistogramBinWidth(result.options.solver.max_iterations);
    if (i < kBins) data << "\"" << i * width + 1 << "-" << (i + 1) * width << "\"";
    else data << "\"failed\"";
    for (int k = 0; k < kStudyMethods; ++k) data << " " << h[k][i];
    data << "\n";
  }
  write(dir / "iterations.dat", data.str());

  std::ostringstream gp;
  gp << "# Fig. 1 of Rucker & Wensing 2022, reproduced: iterations to converge per parameterization.\n"
     << "set terminal pngcairo size 1400,900 font 'sans,11'\n"
     << "set output 'fig1.png'\n"
     << "set multiplot layout 2,2 title 'Iterations to converge, " << result.summary.bodies
     << " bodies (Levenberg-Marquardt, at most " << result.options.solver.max_iterations << " iterations)'\n"
     << "set style data histograms\nset style fill solid 0.8 border -1\nset boxwidth 0.8\n"
     << "set xtics rotate by -45\nset ylabel 'bodies'\nset xlabel 'iterations'\nset grid ytics\nunset key\n";
  const char* titles[kStudyMethods] = {"linear (pi)", "eigenvalue (Section III)", "exponential (Section IV-A)",
                                       "log-Cholesky (Section IV-B)"};
  for (int k = 0; k < kStudyMethods; ++k) {
    gp << "set title '" << titles[k] << ": " << result.summary.methods[k].failures << " failures'\n"
       << "plot 'iterations.dat' using " << k + 2 << ":xtic(1) linecolor rgb '#3060a0'\n";
  }
  gp << "unset multiplot\n";
  write(dir / "fig1.gp", gp.str());

  RunGnuplot(dir, "fig1.gp");
  if (!fs::exists(dir / "fig1.png") || fs::file_size(dir / "fig1.png") == 0) {
    throw std::runtime_error("gnuplot produced no '" + (dir / "fig1.png").string() + "'");
  }
}

}  // namespace inertial
