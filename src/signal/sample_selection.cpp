#include "inertial/signal/sample_selection.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace inertial {

JointSamples SelectSamples(const JointSamples& data, const std::vector<int>& keep_rows) {
  const int N = data.size();
  for (const Eigen::MatrixXd* m : {&data.q, &data.qd, &data.qdd, &data.tau}) {
    if (m->rows() != N) {
      throw std::invalid_argument("SelectSamples: the arrays of the samples must all have " + std::to_string(N) + " rows");
    }
  }
  JointSamples out;
  out.joint_names = data.joint_names;
  const Eigen::Index rows = static_cast<Eigen::Index>(keep_rows.size());
  out.t.resize(rows);
  out.q.resize(rows, data.q.cols());
  out.qd.resize(rows, data.qd.cols());
  out.qdd.resize(rows, data.qdd.cols());
  out.tau.resize(rows, data.tau.cols());
  for (Eigen::Index r = 0; r < rows; ++r) {
    const int i = keep_rows[static_cast<std::size_t>(r)];
    if (i < 0 || i >= N) {
      throw std::invalid_argument("SelectSamples: row " + std::to_string(i) + " is outside the " + std::to_string(N) +
                                  " samples");
    }
    out.t[r] = data.t[i];
    out.q.row(r) = data.q.row(i);
    out.qd.row(r) = data.qd.row(i);
    out.qdd.row(r) = data.qdd.row(i);
    out.tau.row(r) = data.tau.row(i);
  }
  return out;
}

int HoldoutStart(const Eigen::VectorXd& t, double fraction) {
  if (!(fraction > 0.0 && fraction < 1.0)) throw std::invalid_argument("holdout: the fraction must be in (0, 1)");
  const int N = static_cast<int>(t.size());
  int start = N;
  if (N > 0) {
    const double cut = t[N - 1] - fraction * (t[N - 1] - t[0]);
    start = static_cast<int>(std::lower_bound(t.data(), t.data() + N, cut) - t.data());
  }
  if (N - start < 2 || start < 2) {
    throw std::invalid_argument("holdout: " + std::to_string(N) + " samples cannot be split into two parts of at least 2 (" +
                                std::to_string(start) + " before the last " + std::to_string(std::lround(100 * fraction)) +
                                " % of the time, " + std::to_string(N - start) + " in it)");
  }
  return start;
}

std::vector<int> RowsExcept(int n, const std::vector<int>& sorted_rows) {
  std::vector<int> keep;
  keep.reserve(static_cast<std::size_t>(std::max(0, n - static_cast<int>(sorted_rows.size()))));
  std::size_t b = 0;
  for (int i = 0; i < n; ++i) {
    while (b < sorted_rows.size() && sorted_rows[b] < i) ++b;
    if (b < sorted_rows.size() && sorted_rows[b] == i) continue;
    keep.push_back(i);
  }
  return keep;
}

std::vector<int> RowRange(int begin, int end, int stride) {
  std::vector<int> rows;
  for (int i = begin; i < end; i += std::max(1, stride)) rows.push_back(i);
  return rows;
}

}  // namespace inertial
