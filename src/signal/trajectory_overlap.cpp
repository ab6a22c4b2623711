#include "inertial/signal/trajectory_overlap.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

namespace inertial {
namespace {

// Row indices 0..n-1 thinned to at most `cap`, evenly spaced.
std::vector<int> Thinned(int n, int cap) {
  std::vector<int> rows;
  const double stride = std::max(1.0, static_cast<double>(n) / cap);
  for (double r = 0; r < n; r += stride) rows.push_back(static_cast<int>(r));
  return rows;
}

}  // namespace

double RetracedShare(const JointSamples& reference, const JointSamples& other, double tolerance) {
  if (reference.size() == 0 || other.size() == 0) throw std::invalid_argument("retraced share: an empty log");
  const int n = static_cast<int>(reference.q.cols());
  if (other.q.cols() != n || reference.qd.cols() != n || other.qd.cols() != n) {
    throw std::invalid_argument("retraced share: the logs have different joints");
  }
  // State matrix: columns q then qd, scaled by each coordinate's range over both logs.
  auto states = [&](const JointSamples& s, const std::vector<int>& rows) {
    Eigen::MatrixXd x(2 * n, rows.size());
    for (size_t i = 0; i < rows.size(); ++i) {
      x.col(i) << s.q.row(rows[i]).transpose(), s.qd.row(rows[i]).transpose();
    }
    return x;
  };
  const Eigen::MatrixXd a = states(reference, Thinned(reference.size(), 20000));
  const Eigen::MatrixXd b = states(other, Thinned(other.size(), 500));
  Eigen::VectorXd lo = a.rowwise().minCoeff().cwiseMin(b.rowwise().minCoeff());
  Eigen::VectorXd hi = a.rowwise().maxCoeff().cwiseMax(b.rowwise().maxCoeff());
  Eigen::VectorXd eps = tolerance * (hi - lo);
  if (!eps.allFinite()) return 0.0;
  // A coordinate that never moves matches within any positive tolerance.
  for (int k = 0; k < eps.size(); ++k) eps[k] = std::max(eps[k], 1e-12);
  int close = 0;
  for (Eigen::Index j = 0; j < b.cols(); ++j) {
    for (Eigen::Index i = 0; i < a.cols(); ++i) {
      bool near = true;
      for (int k = 0; k < 2 * n && near; ++k) near = std::abs(a(k, i) - b(k, j)) <= eps[k];
      if (near) {
        ++close;
        break;
      }
    }
  }
  return static_cast<double>(close) / static_cast<double>(b.cols());
}

}  // namespace inertial
