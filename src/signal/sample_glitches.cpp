#include "inertial/signal/sample_glitches.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "inertial/signal/robust_statistics.hpp"
#include "inertial/signal/robust_statistics.hpp"
#include "inertial/model/number_text.hpp"

namespace inertial {
namespace {

constexpr int kMinRows = 7;                   // 5 neighbours on one side of an edge row, and itself
constexpr double kRelativeScaleFloor = 1e-3;  // of the column's RMS (header)
constexpr double kAbsoluteScaleFloor = 1e-9;  // (header)
constexpr double kNeighbourhoods = 2.0;       // |d| > 2 r (header)

struct Expectation {
  double value = 0.0;
  double spread = 0.0;  // r_i
};

// Spread of the values without the one furthest from their median.
double TrimmedSpread(std::vector<double> v) {
  std::vector<double> work = v;
  const double median = Median(work);
  auto furthest = std::max_element(v.begin(), v.end(), [median](double a, double b) {
    return std::abs(a - median) < std::abs(b - median);
  });
  v.erase(furthest);
  const auto [lo, hi] = std::minmax_element(v.begin(), v.end());
  return *hi - *lo;
}

Expectation Expect(const Eigen::MatrixXd& m, int column, int i) {
  const int N = static_cast<int>(m.rows());
  std::vector<double> neighbours;
  if (i >= 2 && i <= N - 3) {
    neighbours = {m(i - 2, column), m(i - 1, column), m(i + 1, column), m(i + 2, column)};
    std::vector<double> work = neighbours;
    return {Median(work), TrimmedSpread(neighbours)};
  }
  // Edge rows: the 5 nearest rows on the inside, at signed distances 1..5 from i.
  const int direction = i < 2 ? 1 : -1;
  std::array<double, 5> at{};
  for (int k = 0; k < 5; ++k) at[k] = m(i + direction * (k + 1), column);
  neighbours.assign(at.begin(), at.end());
  std::vector<double> extrapolated;
  for (int a = 0; a < 5; ++a) {
    for (int b = a + 1; b < 5; ++b) {
      // Line through (a + 1, at[a]) and (b + 1, at[b]), evaluated at distance 0.
      const double da = a + 1.0, db = b + 1.0;
      extrapolated.push_back(at[a] + (at[b] - at[a]) * (0.0 - da) / (db - da));
    }
  }
  return {Median(extrapolated), TrimmedSpread(neighbours)};
}

}  // namespace

std::vector<int> GlitchScreen::Rows() const {
  std::vector<int> rows;
  rows.reserve(glitches.size());
  for (const SampleGlitch& g : glitches) rows.push_back(g.row);
  return rows;
}

GlitchScreen FindGlitches(const Eigen::MatrixXd& signals, double threshold) {
  if (!std::isfinite(threshold) || threshold < 0.0) {
    throw std::invalid_argument("FindGlitches: the threshold must be a finite number >= 0");
  }
  if (!signals.allFinite()) throw std::invalid_argument("FindGlitches: the signals must be finite numbers");
  GlitchScreen screen;
  const int N = static_cast<int>(signals.rows()), C = static_cast<int>(signals.cols());
  if (N < kMinRows || C == 0) return screen;
  screen.threshold = threshold > 0.0 ? threshold : DefaultOutlierThreshold(static_cast<long long>(N) * C);
  std::vector<SampleGlitch> worst(static_cast<std::size_t>(N));
  std::vector<double> deviation(static_cast<std::size_t>(N)), spread(static_cast<std::size_t>(N)),
      expected(static_cast<std::size_t>(N));
  for (int c = 0; c < C; ++c) {
    for (int i = 0; i < N; ++i) {
      const Expectation e = Expect(signals, c, i);
      expected[i] = e.value;
      spread[i] = e.spread;
      deviation[i] = signals(i, c) - e.value;
    }
    std::vector<double> work = deviation;
    const double mad = MedianAndMad(work).second;
    // RMS as the mean of squares of values scaled by the largest, so 1e200 does not overflow.
    const double largest = signals.col(c).cwiseAbs().maxCoeff();
    const double rms = largest > 0.0 ? largest * (signals.col(c) / largest).norm() / std::sqrt(static_cast<double>(N)) : 0.0;
    const double scale = std::max({kMadToSigma * mad, kRelativeScaleFloor * rms, kAbsoluteScaleFloor});
    for (int i = 0; i < N; ++i) {
      const double d = std::abs(deviation[i]);
      if (d > screen.threshold * scale && d > kNeighbourhoods * spread[i] && d / scale > worst[i].scales) {
        worst[i] = {i, c, signals(i, c), expected[i], d / scale};
      }
    }
  }
  for (const SampleGlitch& g : worst) {
    if (g.scales > 0.0) screen.glitches.push_back(g);
  }
  return screen;
}

Eigen::MatrixXd BodySignals(const BodyLog& log) {
  const int N = static_cast<int>(log.samples.size());
  const bool gravity = !log.gravity.empty();
  Eigen::MatrixXd m(N, gravity ? 15 : 12);
  for (int i = 0; i < N; ++i) {
    m.row(i).head<6>() = log.samples[i].twist.transpose();
    m.row(i).segment<6>(6) = log.samples[i].wrench.transpose();
    if (gravity) m.row(i).tail<3>() = log.gravity[i].transpose();
  }
  return m;
}

std::vector<std::string> BodySignalNames(const BodyLog& log) {
  std::vector<std::string> names{"wx", "wy", "wz", "vx", "vy", "vz", "mx", "my", "mz", "fx", "fy", "fz"};
  if (!log.gravity.empty()) names.insert(names.end(), {"gx", "gy", "gz"});
  return names;
}

BodyLog SelectBodySamples(const BodyLog& log, const std::vector<int>& keep_rows) {
  const int N = static_cast<int>(log.samples.size());
  if (!log.gravity.empty() && static_cast<int>(log.gravity.size()) != N) {
    throw std::invalid_argument("SelectBodySamples: the log has " + std::to_string(N) + " samples and " +
                                std::to_string(log.gravity.size()) + " gravity vectors");
  }
  BodyLog out;
  out.samples.reserve(keep_rows.size());
  for (const int i : keep_rows) {
    if (i < 0 || i >= N) {
      throw std::invalid_argument("SelectBodySamples: row " + std::to_string(i) + " is outside the " +
                                  std::to_string(N) + " samples");
    }
    out.samples.push_back(log.samples[i]);
    if (!log.gravity.empty()) out.gravity.push_back(log.gravity[i]);
  }
  return out;
}

std::string DescribeGlitch(const BodyLog& log, const SampleGlitch& glitch) {
  const std::vector<std::string> names = BodySignalNames(log);
  const std::string column = glitch.column < static_cast<int>(names.size()) ? names[glitch.column] : "column " + std::to_string(glitch.column);
  const std::string time = glitch.row < static_cast<int>(log.samples.size()) ? FormatNumber(log.samples[glitch.row].t, 4) : "?";
  return "sample " + std::to_string(glitch.row) + " (t = " + time + " s): " + column + " = " + FormatNumber(glitch.value, 4) +
         ", expected " + FormatNumber(glitch.expected, 4) + " from its neighbours (" + FormatNumber(glitch.scales, 4) + " robust scales)";
}

}  // namespace inertial
