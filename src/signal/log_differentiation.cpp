#include "inertial/signal/log_differentiation.hpp"
#include "inertial/signal/robust_statistics.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "inertial/model/number_text.hpp"
#include "inertial/signal/sample_selection.hpp"

namespace inertial {
namespace {

std::string What(bool velocities, bool accelerations) {
  return velocities && accelerations ? "velocities and accelerations" : velocities ? "velocities" : "accelerations";
}

// The sentence on the gaps cut at: their number, the longest and where.
std::string GapNotice(const Eigen::VectorXd& t, const std::vector<int>& starts, double median, double limit,
                      const std::string& what) {
  int longest = starts.front();
  for (int s : starts) {
    if (t[s] - t[s - 1] > t[longest] - t[longest - 1]) longest = s;
  }
  const double gap = t[longest] - t[longest - 1];
  const std::string n = std::to_string(starts.size());
  return (starts.size() == 1 ? "a gap of " + FormatNumber(gap, 4) + " s"
                             : n + " gaps longer than " + FormatNumber(limit, 4) + " s (the longest " +
                                   FormatNumber(gap, 4) + " s)") +
         " after t = " + FormatNumber(t[longest - 1], 10) + " s (" + FormatNumber(gap / median, 3) + " median steps of " +
         FormatNumber(median, 4) + " s): " + what + " are derived in " + std::to_string(starts.size() + 1) +
         " pieces, not across " + (starts.size() == 1 ? "it" : "them");
}

// Differentiates rows [begin, end) of log into out (rows at the same places); throws as documented.
void DerivePiece(const JointSamples& log, int begin, int end, const SavitzkyGolayOptions& options, bool velocities,
                 SavitzkyGolayResult* out) {
  SavitzkyGolayResult sg;
  try {
    sg = SavitzkyGolay(log.t.segment(begin, end - begin), log.q.middleRows(begin, end - begin), options);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(std::string("cannot derive ") + (velocities ? "velocities" : "accelerations") +
                                " from q: " + e.what());
  }
  out->first.middleRows(begin, end - begin) = sg.first;
  out->second.middleRows(begin, end - begin) = sg.second;
}

}  // namespace

double GapLimit(const Eigen::VectorXd& t, const SavitzkyGolayOptions& options) {
  return std::max(kGapMedianSteps * MedianStep(t), 0.5 * options.window);
}

std::vector<int> GapStarts(const Eigen::VectorXd& t, const SavitzkyGolayOptions& options) {
  std::vector<int> starts;
  if (t.size() < 4) return starts;
  const double limit = GapLimit(t, options);
  for (Eigen::Index i = 1; i < t.size(); ++i) {
    if (t[i] - t[i - 1] > limit) starts.push_back(static_cast<int>(i));
  }
  return starts;
}

LogDerivation DeriveFromPositions(JointSamples* log, bool velocities, bool accelerations, const SavitzkyGolayOptions& options) {
  LogDerivation d;
  if (!velocities && !accelerations) return d;
  const std::string what = What(velocities, accelerations);
  const std::vector<int> gaps = GapStarts(log->t, options);
  std::vector<int> bounds{0};
  bounds.insert(bounds.end(), gaps.begin(), gaps.end());
  bounds.push_back(log->size());
  // Pieces too short for the polynomial are left out (when at least one piece is long enough).
  std::vector<int> keep;
  std::vector<std::pair<int, int>> short_pieces;
  for (size_t p = 0; p + 1 < bounds.size(); ++p) {
    if (bounds.size() > 2 && bounds[p + 1] - bounds[p] < options.order + 1) {
      short_pieces.emplace_back(bounds[p], bounds[p + 1]);
      for (int i = bounds[p]; i < bounds[p + 1]; ++i) d.left_out.push_back(i);
    }
  }
  if (!d.left_out.empty() && static_cast<int>(d.left_out.size()) < log->size()) {
    const Eigen::VectorXd t = log->t;
    d.notices.push_back(std::to_string(d.left_out.size()) + " sample" + (d.left_out.size() > 1 ? "s" : "") + " in " +
                        std::to_string(short_pieces.size()) + " piece" + (short_pieces.size() > 1 ? "s" : "") +
                        " between gaps (the first from t = " + FormatNumber(t[short_pieces[0].first], 10) + " s) " +
                        (d.left_out.size() > 1 ? "are" : "is") + " too few for a polynomial of order " +
                        std::to_string(options.order) + ": left out");
    *log = SelectSamples(*log, RowsExcept(log->size(), d.left_out));
    LogDerivation rest = DeriveFromPositions(log, velocities, accelerations, options);  // the pieces left
    rest.notices.insert(rest.notices.begin(), d.notices.begin(), d.notices.end());
    rest.left_out = std::move(d.left_out);
    return rest;
  }
  SavitzkyGolayResult sg{Eigen::MatrixXd(), Eigen::MatrixXd(log->q.rows(), log->q.cols()),
                         Eigen::MatrixXd(log->q.rows(), log->q.cols())};
  for (size_t p = 0; p + 1 < bounds.size(); ++p) DerivePiece(*log, bounds[p], bounds[p + 1], options, velocities, &sg);
  for (Eigen::Index i = 0; i < log->q.rows(); ++i) {
    const bool qd_ok = !velocities || sg.first.row(i).allFinite();
    if (!qd_ok || (accelerations && !sg.second.row(i).allFinite())) {
      throw std::invalid_argument(std::string("the ") + (qd_ok ? "accelerations" : "velocities") +
                                  " derived from q are not finite at sample " + std::to_string(i) + " (t = " +
                                  FormatNumber(log->t[i], 10) + " s): q too large for its time steps");
    }
  }
  if (velocities) log->qd = std::move(sg.first);
  if (accelerations) log->qdd = std::move(sg.second);
  d.notices.push_back(what + " derived from q by Savitzky-Golay (order " + std::to_string(options.order) + ", window " +
                      FormatNumberExact(options.window) + " s, on the log's time stamps)");
  if (!gaps.empty()) d.notices.push_back(GapNotice(log->t, gaps, MedianStep(log->t), GapLimit(log->t, options), what));
  d.piece_starts = {0};
  d.piece_starts.insert(d.piece_starts.end(), gaps.begin(), gaps.end());
  return d;
}

}  // namespace inertial
