#include "inertial/signal/recorded_runs.hpp"
#include "inertial/signal/robust_statistics.hpp"

#include <algorithm>
#include <stdexcept>

#include "inertial/signal/sample_selection.hpp"

namespace inertial {
namespace {

// Appends rows of `run` (shifted by `shift`) to *out, which has `rows` filled.
void Append(const JointSamples& run, double shift, int rows, JointSamples* out) {
  const int n = run.size();
  out->t.segment(rows, n) = run.t.array() + shift;
  out->q.middleRows(rows, n) = run.q;
  out->qd.middleRows(rows, n) = run.qd;
  out->qdd.middleRows(rows, n) = run.qdd;
  out->tau.middleRows(rows, n) = run.tau;
}

}  // namespace

JointSamples RecordedRuns::Run(int k) const {
  return SelectSamples(samples, RowRange(starts.at(static_cast<size_t>(k)), starts.at(static_cast<size_t>(k) + 1)));
}

RecordedRuns JoinRuns(const std::vector<std::string>& names, const std::vector<JointSamples>& runs) {
  if (runs.empty() || names.size() != runs.size()) {
    throw std::invalid_argument("runs: give one name per run and at least one run");
  }
  RecordedRuns out;
  out.names = names;
  int total = 0;
  for (size_t k = 0; k < runs.size(); ++k) {
    if (runs[k].size() == 0) throw std::invalid_argument(names[k] + ": the run has no samples");
    if (runs[k].joint_names != runs[0].joint_names || runs[k].q.cols() != runs[0].q.cols()) {
      throw std::invalid_argument(names[k] + ": its joints differ from those of " + names[0]);
    }
    total += runs[k].size();
  }
  const int J = static_cast<int>(runs[0].q.cols());
  JointSamples& s = out.samples;
  s.joint_names = runs[0].joint_names;
  s.t.resize(total);
  s.q.resize(total, J);
  s.qd.resize(total, J);
  s.qdd.resize(total, J);
  s.tau.resize(total, J);
  int rows = 0;
  double end = 0.0;
  for (size_t k = 0; k < runs.size(); ++k) {
    const JointSamples& run = runs[k];
    const double shift =
        k == 0 ? 0.0 : end + std::max(kRunSeparation, runs[k - 1].size() > 1 ? 10.0 * MedianStep(runs[k - 1].t) : 0.0) - run.t[0];
    out.starts.push_back(rows);
    out.shifts.push_back(shift);
    Append(run, shift, rows, &s);
    rows += run.size();
    end = run.t[run.size() - 1] + shift;
  }
  out.starts.push_back(rows);
  return out;
}

void SplitRunsHoldout(const RecordedRuns& runs, double fraction, RecordedRuns* train, RecordedRuns* validation) {
  std::vector<int> train_rows, held_rows;
  for (int k = 0; k < runs.num_runs(); ++k) {
    const int begin = runs.starts[static_cast<size_t>(k)], end = runs.starts[static_cast<size_t>(k) + 1];
    int start = 0;
    try {
      start = begin + HoldoutStart(runs.samples.t.segment(begin, end - begin), fraction);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(runs.names[static_cast<size_t>(k)] + ": " + e.what());
    }
    for (int i = begin; i < end; ++i) (i < start ? train_rows : held_rows).push_back(i);
  }
  for (auto [part, rows] : {std::pair{train, &train_rows}, std::pair{validation, &held_rows}}) {
    part->names = runs.names;
    part->shifts = runs.shifts;
    part->samples = SelectSamples(runs.samples, *rows);
    part->starts.assign(1, 0);
    for (int k = 0; k < runs.num_runs(); ++k) {
      const int end = runs.starts[static_cast<size_t>(k) + 1];
      part->starts.push_back(static_cast<int>(std::count_if(rows->begin(), rows->end(), [&](int i) { return i < end; })));
    }
  }
}

}  // namespace inertial
