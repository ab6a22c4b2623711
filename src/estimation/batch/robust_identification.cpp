#include "inertial/estimation/batch/robust_identification.hpp"

#include "inertial/signal/robust_statistics.hpp"
#include "inertial/model/number_text.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iterator>
#include <limits>
#include <stdexcept>
#include <tuple>
#include <utility>

namespace inertial {
namespace {

constexpr double kRelativeScaleFloor = 1e-3;  // of the RMS measured torque (header)
constexpr double kAbsoluteScaleFloor = 1e-9;  // N m or N (header)
constexpr double kExtremeScales = 1e6;        // DescribeExtremeValues (header)
constexpr double kExtremeRelativeFloor = 1e-6;
constexpr int kReasonRows = 5;                // rejected rows explained in OutlierReport::reasons

std::string Where(const JointSamples& data, int i) {
  return "sample " + std::to_string(i) + " (t = " + FormatNumber(data.t[i], 4) + " s)";
}

const char* const kColumnPrefixes[] = {"q_", "qd_", "qdd_", "tau_"};

const Eigen::MatrixXd& ColumnBlock(const JointSamples& data, int kind) {
  switch (kind) {
    case 0: return data.q;
    case 1: return data.qd;
    case 2: return data.qdd;
    default: return data.tau;
  }
}

/// Step 1 for one row: "" if q, qd, qdd, tau are finite, else the reason naming the first bad column.
std::string NonFiniteColumn(const JointSamples& data, int i) {
  for (int kind = 0; kind < 4; ++kind) {
    const Eigen::MatrixXd& m = ColumnBlock(data, kind);
    for (int j = 0; j < m.cols(); ++j) {
      if (!std::isfinite(m(i, j))) return "non-finite " + std::string(kColumnPrefixes[kind]) + data.joint_names[j];
    }
  }
  return "";
}

/// The largest |value| among the row's q, qd, qdd, as "qd_hip = 1e+300", to explain a non-finite regressor.
std::string LargestMotionValue(const JointSamples& data, int i) {
  int best_kind = 0, best_joint = 0;
  double best = -1.0;
  for (int kind = 0; kind < 3; ++kind) {
    const Eigen::MatrixXd& m = ColumnBlock(data, kind);
    for (int j = 0; j < m.cols(); ++j) {
      if (std::abs(m(i, j)) > best) {
        best = std::abs(m(i, j));
        best_kind = kind;
        best_joint = j;
      }
    }
  }
  return kColumnPrefixes[best_kind] + data.joint_names[best_joint] + " = " + FormatNumber(ColumnBlock(data, best_kind)(i, best_joint), 4);
}

/// Residuals A_i w - tau_i (one row per entry of `rows`); the regressor of a row whose values are
/// finite may still overflow, giving a non-finite residual row.
Eigen::MatrixXd Residuals(const RobotDynamics& model, const JointSamples& data, const std::vector<int>& rows,
                          const Eigen::VectorXd& w) {
  const int n = model.num_dofs();
  TreeWorkspace workspace = model.MakeWorkspace();
  Eigen::MatrixXd A(n, model.num_features());
  Eigen::VectorXd q(n), qd(n), qdd(n);
  Eigen::MatrixXd r(static_cast<Eigen::Index>(rows.size()), n);
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const int i = rows[k];
    q = data.q.row(i).transpose();
    qd = data.qd.row(i).transpose();
    qdd = data.qdd.row(i).transpose();
    model.Features(q, qd, qdd, &workspace, A);
    if (!A.allFinite()) {
      r.row(static_cast<Eigen::Index>(k)).setConstant(std::numeric_limits<double>::quiet_NaN());
      continue;
    }
    r.row(static_cast<Eigen::Index>(k)) = (A * w).transpose() - data.tau.row(i);
  }
  return r;
}

/// One classification of the candidate rows by their residuals.
struct Classification {
  std::vector<int> rejected;          // candidate rows rejected, ascending
  std::vector<std::string> reasons;   // for the first kReasonRows of them
  Eigen::MatrixXd center, scale;      // per run (rows) and joint
};

/// Rows whose residual is non-finite, or beyond k s_j of m_j for some joint j, with m_j and s_j
/// those of the row's run (run_of: each candidate's run).
Classification Classify(const JointSamples& data, const std::vector<int>& candidates, const Eigen::MatrixXd& residuals,
                        double k, const Eigen::MatrixXd& scale_floor, const std::vector<int>& run_of,
                        const std::string& model_name) {
  const int n = static_cast<int>(residuals.cols()), runs = static_cast<int>(scale_floor.rows());
  Classification c;
  c.center.resize(runs, n);
  c.scale.resize(runs, n);
  std::vector<double> column;
  column.reserve(candidates.size());
  for (int run = 0; run < runs; ++run) {
    for (int j = 0; j < n; ++j) {
      column.clear();
      for (Eigen::Index r = 0; r < residuals.rows(); ++r) {
        if (run_of[static_cast<std::size_t>(r)] == run && std::isfinite(residuals(r, j))) column.push_back(residuals(r, j));
      }
      double median = 0.0, mad = 0.0;
      if (!column.empty()) std::tie(median, mad) = MedianAndMad(column);
      c.center(run, j) = median;
      c.scale(run, j) = std::max(kMadToSigma * mad, scale_floor(run, j));
    }
  }
  for (std::size_t row = 0; row < candidates.size(); ++row) {
    const auto r = residuals.row(static_cast<Eigen::Index>(row));
    const int i = candidates[row];
    const Eigen::Index run = run_of[row];
    if (!r.allFinite()) {
      c.rejected.push_back(i);
      if (static_cast<int>(c.reasons.size()) < kReasonRows) {
        c.reasons.push_back(Where(data, i) + ": the " + model_name + "'s prediction is not finite (" +
                            LargestMotionValue(data, i) + ")");
      }
      continue;
    }
    int worst = 0;
    double worst_ratio = -1.0;
    for (int j = 0; j < n; ++j) {
      const double ratio = std::abs(r[j] - c.center(run, j)) / c.scale(run, j);
      if (ratio > worst_ratio) {
        worst_ratio = ratio;
        worst = j;
      }
    }
    if (!(worst_ratio > k)) continue;
    c.rejected.push_back(i);
    if (static_cast<int>(c.reasons.size()) < kReasonRows) {
      c.reasons.push_back(Where(data, i) + ": residual of the " + model_name + " on " + data.joint_names[worst] + " " +
                          FormatNumber(r[worst], 4) + " (median " + FormatNumber(c.center(run, worst), 4) + "), beyond k s = " + FormatNumber(k, 4) +
                          " x " + FormatNumber(c.scale(run, worst), 4) + " = " + FormatNumber(k * c.scale(run, worst), 4));
    }
  }
  return c;
}

/// Per joint: 1e-3 of the RMS of the measured torque over the candidate rows within k robust
/// scales of the column's median, and at least kAbsoluteScaleFloor.
Eigen::VectorXd ScaleFloor(const JointSamples& data, const std::vector<int>& candidates, double k) {
  const int n = static_cast<int>(data.tau.cols());
  Eigen::VectorXd floor(n);
  if (candidates.empty()) return Eigen::VectorXd::Constant(n, kAbsoluteScaleFloor);  // a run of only bad rows
  std::vector<double> column(candidates.size());
  for (int j = 0; j < n; ++j) {
    for (std::size_t r = 0; r < candidates.size(); ++r) column[r] = data.tau(candidates[r], j);
    std::vector<double> work = column;
    const auto [median, mad] = MedianAndMad(work);
    const double limit = k * kMadToSigma * mad;
    double largest = 0.0;
    for (double v : column) {
      if (std::abs(v - median) <= limit) largest = std::max(largest, std::abs(v));
    }
    double sum = 0.0;
    int count = 0;
    for (double v : column) {
      if (std::abs(v - median) <= limit) {
        const double scaled = largest > 0.0 ? v / largest : 0.0;  // no overflow of the squares
        sum += scaled * scaled;
        ++count;
      }
    }
    const double rms = count > 0 ? largest * std::sqrt(sum / count) : 0.0;
    floor[j] = std::max(kRelativeScaleFloor * rms, kAbsoluteScaleFloor);
  }
  return floor;
}

/// Merges the step-1 rejections with a classification into the report's rejected list and reasons.
void Report(const std::vector<int>& non_finite, const std::vector<std::string>& non_finite_reasons, const Classification& c,
            OutlierReport* report) {
  report->rejected.clear();
  std::merge(non_finite.begin(), non_finite.end(), c.rejected.begin(), c.rejected.end(), std::back_inserter(report->rejected));
  report->non_finite = non_finite;
  report->reasons.clear();
  std::size_t a = 0, b = 0;
  while (static_cast<int>(report->reasons.size()) < kReasonRows) {
    const bool take_a = a < non_finite_reasons.size() && (b >= c.reasons.size() || non_finite[a] < c.rejected[b]);
    if (take_a) {
      report->reasons.push_back(non_finite_reasons[a++]);
    } else if (b < c.reasons.size()) {
      report->reasons.push_back(c.reasons[b++]);
    } else {
      break;
    }
  }
  report->run_center = c.center;
  report->run_scale = c.scale;
  report->center = c.center.row(0).transpose();
  report->scale = c.scale.row(0).transpose();
}

/// Step 1 of the robust fit: the rows that stay candidates (their residuals by the prior, in order)
/// and those set aside for good for non-finite values, with the first kReasonRows reasons.
struct FiniteRows {
  std::vector<int> candidates, non_finite;
  Eigen::MatrixXd residuals;
  std::vector<std::string> non_finite_reasons;
};

/// Sets aside the rows with non-finite values, regressor or prior prediction.
FiniteRows SplitNonFiniteRows(const RobotDynamics& model, const JointSamples& data) {
  const int N = data.size();
  FiniteRows split;
  std::vector<int> finite_values;
  for (int i = 0; i < N; ++i) {
    if (NonFiniteColumn(data, i).empty()) finite_values.push_back(i);
  }
  Eigen::MatrixXd& residuals = split.residuals;
  residuals = Residuals(model, data, finite_values, model.Coefficients(PriorParametersWithoutEffects(model)));
  std::vector<int>& candidates = split.candidates;
  std::vector<int>& non_finite = split.non_finite;
  std::vector<Eigen::Index> candidate_rows;  // into residuals
  for (int i = 0, r = 0; i < N; ++i) {
    const bool values_finite = r < static_cast<int>(finite_values.size()) && finite_values[r] == i;
    if (values_finite && residuals.row(r).allFinite()) {
      candidates.push_back(i);
      candidate_rows.push_back(r);
    } else {
      non_finite.push_back(i);
    }
    if (values_finite) ++r;
  }
  if (candidates.size() != finite_values.size()) residuals = Eigen::MatrixXd(residuals(candidate_rows, Eigen::all));
  std::vector<std::string>& non_finite_reasons = split.non_finite_reasons;
  for (int i : non_finite) {
    if (static_cast<int>(non_finite_reasons.size()) >= kReasonRows) break;
    const std::string column = NonFiniteColumn(data, i);
    non_finite_reasons.push_back(Where(data, i) + ": " +
                                 (column.empty() ? "the regressor or the prior's prediction is not finite (" +
                                                       LargestMotionValue(data, i) + ")"
                                                 : column));
  }
  return split;
}

}  // namespace

RobustIdentificationResult IdentifyJointModelRobust(const RobotDynamics& model, const JointSamples& data,
                                                    const JointIdentificationOptions& options,
                                                    const OutlierOptions& outliers) {
  RobustIdentificationResult result;
  if (!outliers.enabled) {
    result.equations = AccumulateNormalEquations(model, data);
    result.fit = IdentifyJointModel(model, result.equations, options);
    return result;
  }
  if (outliers.max_rounds < 1) throw std::invalid_argument("robust identification: max_rounds must be at least 1");
  if (!(outliers.threshold >= 0.0) || !std::isfinite(outliers.threshold)) {
    throw std::invalid_argument("robust identification: the threshold must be finite and non-negative (0: automatic)");
  }
  // Checks the names and sizes exactly as the fit will (on an empty selection: cheap).
  AccumulateNormalEquations(model, SelectSamples(data, {}));
  const int N = data.size(), n = model.num_dofs();

  // Step 1: rows with non-finite values, regressor or prior prediction, for good.
  FiniteRows split = SplitNonFiniteRows(model, data);
  const std::vector<int>& candidates = split.candidates;
  const std::vector<int>& non_finite = split.non_finite;
  const std::vector<std::string>& non_finite_reasons = split.non_finite_reasons;
  Eigen::MatrixXd& residuals = split.residuals;
  if (N == 0) throw std::invalid_argument("robust identification: no samples");
  if (candidates.empty()) {
    std::string first;
    for (const std::string& r : non_finite_reasons) first += (first.empty() ? "" : "; ") + r;
    throw std::invalid_argument("robust identification: no usable sample (" + first + ")");
  }

  // Step 2: the prior's residuals.
  const double k = outliers.threshold > 0.0 ? outliers.threshold
                                            : DefaultOutlierThreshold(static_cast<long long>(candidates.size()) * n);
  // The runs (OutlierOptions::run_starts): each candidate's, and the scale floor of each.
  const std::vector<int> starts = outliers.run_starts.empty() ? std::vector<int>{0, N} : outliers.run_starts;
  const int runs = static_cast<int>(starts.size()) - 1;
  if (runs < 1 || starts.front() != 0 || starts.back() != N || !std::is_sorted(starts.begin(), starts.end())) {
    throw std::invalid_argument("robust identification: run_starts must rise from 0 to the number of samples");
  }
  std::vector<int> run_of(candidates.size());
  for (std::size_t r = 0; r < candidates.size(); ++r) {
    run_of[r] = static_cast<int>(std::upper_bound(starts.begin(), starts.end(), candidates[r]) - starts.begin()) - 1;
  }
  Eigen::MatrixXd floor(runs, n);
  for (int run = 0; run < runs; ++run) {
    std::vector<int> in_run;
    for (std::size_t r = 0; r < candidates.size(); ++r) {
      if (run_of[r] == run) in_run.push_back(candidates[r]);
    }
    floor.row(run) = ScaleFloor(data, in_run, k).transpose();
  }
  Classification current = Classify(data, candidates, residuals, k, floor, run_of, "prior");

  // Step 3: fit on the kept rows, classify every row by that fit, until the set is unchanged.
  OutlierReport& report = result.outliers;
  report.threshold = k;
  for (int round = 1; round <= outliers.max_rounds; ++round) {
    std::vector<int> kept;
    kept.reserve(candidates.size());
    std::set_difference(candidates.begin(), candidates.end(), current.rejected.begin(), current.rejected.end(),
                        std::back_inserter(kept));
    if (kept.empty()) throw std::invalid_argument("robust identification: every sample was rejected");
    result.equations = AccumulateNormalEquations(model, SelectSamples(data, kept));
    result.fit = IdentifyJointModel(model, result.equations, options);
    report.rounds = round;
    residuals = Residuals(model, data, candidates, model.Coefficients(result.fit.x));
    Classification next = Classify(data, candidates, residuals, k, floor, run_of, "fit");
    if (next.rejected == current.rejected) {
      report.settled = true;
      current = std::move(next);  // the same rows; scales and reasons of the returned fit
      break;
    }
    if (round == outliers.max_rounds) break;  // the fit's own set stays (it is what the fit used)
    current = std::move(next);
  }
  Report(non_finite, non_finite_reasons, current, &report);
  report.rows_by_run.assign(static_cast<std::size_t>(runs), 0);
  report.rejected_by_run.assign(static_cast<std::size_t>(runs), 0);
  for (int run = 0; run < runs; ++run) report.rows_by_run[static_cast<std::size_t>(run)] = starts[run + 1] - starts[run];
  for (int i : report.rejected) {
    ++report.rejected_by_run[static_cast<std::size_t>(std::upper_bound(starts.begin(), starts.end(), i) - starts.begin() - 1)];
  }
  return result;
}

std::vector<std::string> DescribeExtremeValues(const JointSamples& data, int max_items) {
  struct Item {
    int sample = 0, kind = 0, joint = 0;
    double ratio = 0.0, median = 0.0;  // ratio: +inf for non-finite values
  };
  std::vector<Item> items;
  const int N = data.size();
  std::vector<double> finite;
  for (int kind = 0; kind < 4; ++kind) {
    const Eigen::MatrixXd& m = ColumnBlock(data, kind);
    if (m.rows() != N) continue;
    for (int j = 0; j < m.cols() && j < static_cast<int>(data.joint_names.size()); ++j) {
      finite.clear();
      for (int i = 0; i < N; ++i) {
        if (std::isfinite(m(i, j))) finite.push_back(m(i, j));
      }
      double median = 0.0, scale = 0.0;
      if (!finite.empty()) {
        std::vector<double> magnitudes(finite.size());
        std::transform(finite.begin(), finite.end(), magnitudes.begin(), [](double v) { return std::abs(v); });
        const double median_magnitude = Median(magnitudes);
        const auto [center, mad] = MedianAndMad(finite);
        median = center;
        scale = std::max({kMadToSigma * mad, kExtremeRelativeFloor * median_magnitude, 1e-300});
      }
      for (int i = 0; i < N; ++i) {
        const double v = m(i, j);
        if (!std::isfinite(v)) {
          items.push_back({i, kind, j, std::numeric_limits<double>::infinity(), median});
        } else if (!finite.empty()) {
          const double ratio = std::abs(v - median) / scale;
          if (ratio > kExtremeScales) items.push_back({i, kind, j, ratio, median});
        }
      }
    }
  }
  // Non-finite values first in sample order, then the most extreme.
  std::stable_sort(items.begin(), items.end(), [](const Item& a, const Item& b) {
    const bool a_inf = std::isinf(a.ratio), b_inf = std::isinf(b.ratio);
    if (a_inf != b_inf) return a_inf;
    if (a_inf) return a.sample < b.sample;
    return a.ratio > b.ratio;
  });
  std::vector<std::string> out;
  for (const Item& item : items) {
    if (static_cast<int>(out.size()) >= max_items) break;
    const double v = ColumnBlock(data, item.kind)(item.sample, item.joint);
    std::string text = "sample " + std::to_string(item.sample) +
                       (item.sample < data.t.size() ? " (t = " + FormatNumber(data.t[item.sample], 4) + " s)" : std::string()) +
                       ": " + kColumnPrefixes[item.kind] + data.joint_names[item.joint] + " = " + FormatNumber(v, 4);
    text += std::isinf(item.ratio) ? " (not finite)"
                                   : ", " + FormatNumber(item.ratio, 4) + " robust scales from the column's median " + FormatNumber(item.median, 4);
    out.push_back(text);
  }
  return out;
}

}  // namespace inertial
