#include "inertial/signal/savitzky_golay.hpp"
#include "inertial/model/number_text.hpp"

#include <Eigen/Core>
#include <algorithm>
#include <charconv>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace inertial {
namespace {

void CheckInputs(const Eigen::VectorXd& t, const Eigen::MatrixXd& x, const SavitzkyGolayOptions& options) {
  const std::string where = "SavitzkyGolay: ";
  if (options.order < 2) {
    throw std::invalid_argument(where + "order " + std::to_string(options.order) +
                                " is below 2 (the second derivative needs a polynomial of order >= 2)");
  }
  if (!(options.window > 0.0) || !std::isfinite(options.window)) {
    throw std::invalid_argument(where + "window " + FormatNumberExact(options.window) + " s is not a positive finite width");
  }
  if (t.size() != x.rows()) {
    throw std::invalid_argument(where + "t has " + std::to_string(t.size()) + " samples but x has " +
                                std::to_string(x.rows()) + " rows");
  }
  if (t.size() < options.order + 1) {
    throw std::invalid_argument(where + std::to_string(t.size()) + " samples are too few for a polynomial of order " +
                                std::to_string(options.order) + " (at least " + std::to_string(options.order + 1) +
                                " needed)");
  }
  for (Eigen::Index i = 0; i < t.size(); ++i) {
    if (!std::isfinite(t[i])) throw std::invalid_argument(where + "t[" + std::to_string(i) + "] = " + FormatNumberExact(t[i]) + " is not finite");
    if (i > 0 && !(t[i] > t[i - 1])) {
      throw std::invalid_argument(where + "t is not strictly increasing: t[" + std::to_string(i) + "] = " + FormatNumberExact(t[i]) +
                                  " is not after t[" + std::to_string(i - 1) + "] = " + FormatNumberExact(t[i - 1]));
    }
  }
  if (!x.allFinite()) {
    for (Eigen::Index j = 0; j < x.cols(); ++j) {
      for (Eigen::Index i = 0; i < x.rows(); ++i) {
        if (!std::isfinite(x(i, j))) {
          throw std::invalid_argument(where + "x(" + std::to_string(i) + ", " + std::to_string(j) + ") = " + FormatNumberExact(x(i, j)) +
                                      " is not finite");
        }
      }
    }
  }
}

/// Half-open sample range [begin, end) fitted for one sample.
struct Window {
  Eigen::Index begin = 0;
  Eigen::Index end = 0;
};

/// The window of sample i (see the header): centred, shifted at the ends, widened to the nearest
/// `min_count` samples when too sparse.
Window WindowOf(const Eigen::VectorXd& t, Eigen::Index i, double width, Eigen::Index min_count) {
  const Eigen::Index N = t.size();
  const double first = t[0];
  const double last = t[N - 1];
  double lo = t[i] - 0.5 * width;
  double hi = t[i] + 0.5 * width;
  if (last - first <= width) {
    lo = first;
    hi = last;
  } else if (lo < first) {
    lo = first;
    hi = first + width;
  } else if (hi > last) {
    lo = last - width;
    hi = last;
  }
  const double tolerance = 1e-9 * width;
  const double* data = t.data();
  Window w;
  w.begin = std::lower_bound(data, data + N, lo - tolerance) - data;
  w.end = std::upper_bound(data, data + N, hi + tolerance) - data;
  if (w.end - w.begin >= min_count) return w;
  // Too sparse: the min_count samples nearest to t_i.
  w.begin = i;
  w.end = i + 1;
  while (w.end - w.begin < min_count) {
    if (w.begin == 0) {
      ++w.end;
    } else if (w.end == N) {
      --w.begin;
    } else if (t[i] - t[w.begin - 1] <= t[w.end] - t[i]) {
      --w.begin;
    } else {
      ++w.end;
    }
  }
  return w;
}

}  // namespace

SavitzkyGolayResult SavitzkyGolay(const Eigen::VectorXd& t, const Eigen::MatrixXd& x, const SavitzkyGolayOptions& options) {
  CheckInputs(t, x, options);
  const Eigen::Index N = t.size();
  const Eigen::Index m = x.cols();
  const Eigen::Index p1 = options.order + 1;  // number of coefficients

  std::vector<Window> windows(static_cast<std::size_t>(N));
  Eigen::Index max_count = 0;
  for (Eigen::Index i = 0; i < N; ++i) {
    windows[static_cast<std::size_t>(i)] = WindowOf(t, i, options.window, p1);
    max_count = std::max(max_count, windows[static_cast<std::size_t>(i)].end - windows[static_cast<std::size_t>(i)].begin);
  }

  SavitzkyGolayResult result;
  result.value.resize(N, m);
  result.first.resize(N, m);
  result.second.resize(N, m);

  // Work space, allocated once: Q (scaled Vandermonde, orthonormalized in place), R, Y = Q^T x.
  Eigen::MatrixXd q_buffer(max_count, p1);
  Eigen::MatrixXd R(p1, p1);
  Eigen::MatrixXd Y(p1, m);

  for (Eigen::Index i = 0; i < N; ++i) {
    const Window& w = windows[static_cast<std::size_t>(i)];
    const Eigen::Index n = w.end - w.begin;
    const double ti = t[i];
    const double scale = std::max(ti - t[w.begin], t[w.end - 1] - ti);  // > 0: n >= 3 distinct times

    auto Q = q_buffer.topRows(n);
    for (Eigen::Index r = 0; r < n; ++r) {
      const double s = (t[w.begin + r] - ti) / scale;
      double power = 1.0;
      for (Eigen::Index k = 0; k < p1; ++k) {
        Q(r, k) = power;
        power *= s;
      }
    }
    // Modified Gram-Schmidt, twice per column ("twice is enough"): Q orthonormal, V = Q R.
    R.setZero();
    for (Eigen::Index k = 0; k < p1; ++k) {
      for (int pass = 0; pass < 2; ++pass) {
        for (Eigen::Index j = 0; j < k; ++j) {
          const double r = Q.col(j).dot(Q.col(k));
          R(j, k) += r;
          Q.col(k) -= r * Q.col(j);
        }
      }
      R(k, k) = Q.col(k).norm();
      Q.col(k) /= R(k, k);
    }
    Y.noalias() = Q.transpose() * x.middleRows(w.begin, n);
    R.triangularView<Eigen::Upper>().solveInPlace(Y);  // Y = polynomial coefficients in s

    result.value.row(i) = Y.row(0);
    result.first.row(i) = Y.row(1) / scale;
    result.second.row(i) = (2.0 / (scale * scale)) * Y.row(2);
  }
  return result;
}

}  // namespace inertial
