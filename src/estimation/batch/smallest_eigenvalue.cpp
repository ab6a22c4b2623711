#include "inertial/estimation/batch/smallest_eigenvalue.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace inertial {
namespace {

// The number of eigenvalues of the tridiagonal (d, e) below x: negative pivots of T - x I.
int CountBelow(const Eigen::VectorXd& d, const Eigen::VectorXd& e, double x, double tiny) {
  int count = 0;
  double q = d[0] - x;
  if (q < 0) ++count;
  for (int i = 1; i < d.size(); ++i) {
    if (q == 0.0) q = tiny;  // a zero pivot: perturb it (changes the count only at x = an eigenvalue)
    q = d[i] - x - e[i - 1] * e[i - 1] / q;
    if (q < 0) ++count;
  }
  return count;
}

}  // namespace

double SmallestEigenvalue(const Eigen::MatrixXd& S, double relative_tolerance) {
  if (S.rows() != S.cols() || S.rows() == 0) {
    throw std::invalid_argument("smallest eigenvalue: the matrix must be square and non-empty");
  }
  if (!(relative_tolerance >= 0.0)) throw std::invalid_argument("smallest eigenvalue: negative tolerance");
  if (!S.allFinite()) return std::numeric_limits<double>::quiet_NaN();
  const int n = static_cast<int>(S.rows());
  if (n == 1) return S(0, 0);
  const Eigen::Tridiagonalization<Eigen::MatrixXd> tri(S);
  const Eigen::VectorXd d = tri.diagonal();
  const Eigen::VectorXd e = tri.subDiagonal();
  // Gershgorin's interval of T holds every eigenvalue.
  double lo = std::numeric_limits<double>::infinity(), hi = -lo, scale = 0.0;
  for (int i = 0; i < n; ++i) {
    const double r = (i > 0 ? std::abs(e[i - 1]) : 0.0) + (i + 1 < n ? std::abs(e[i]) : 0.0);
    lo = std::min(lo, d[i] - r);
    hi = std::max(hi, d[i] + r);
    scale = std::max({scale, std::abs(d[i] - r), std::abs(d[i] + r)});
  }
  const double tiny = std::numeric_limits<double>::epsilon() * std::max(scale, std::numeric_limits<double>::min());
  // Invariant: fewer than one eigenvalue below lo, at least one below hi.
  // lo is a lower bound throughout; stop once the bracket is within the tolerance of |lambda|
  // (|lambda| >= min(|lo|, |hi|) when both have one sign, else the bracket holds 0).
  const double resolution = 4.0 * tiny;
  for (int step = 0; step < 200; ++step) {
    const double magnitude = lo * hi > 0 ? std::min(std::abs(lo), std::abs(hi)) : 0.0;
    if (hi - lo <= std::max(relative_tolerance * magnitude, resolution)) break;
    const double mid = 0.5 * (lo + hi);
    if (mid <= lo || mid >= hi) break;
    (CountBelow(d, e, mid, tiny) >= 1 ? hi : lo) = mid;
  }
  return lo;
}

}  // namespace inertial
