#include "inertial/diagnosis/residual_analysis.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace inertial {
namespace {

// Slope of a on b with an intercept (0 if b does not vary).
double Slope(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  const Eigen::VectorXd ca = a.array() - a.mean(), cb = b.array() - b.mean();
  const double v = cb.squaredNorm();
  return v > 0.0 ? ca.dot(cb) / v : 0.0;
}

double Correlation(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  const Eigen::VectorXd ca = a.array() - a.mean(), cb = b.array() - b.mean();
  const double d = std::sqrt(ca.squaredNorm() * cb.squaredNorm());
  return d > 0.0 ? ca.dot(cb) / d : 0.0;
}

}  // namespace

ResidualAnalysis AnalyzeResiduals(const JointSamples& data, const Eigen::MatrixXd& predicted, double window_seconds,
                                  int num_windows) {
  const int N = data.size(), n = static_cast<int>(data.tau.cols());
  if (N == 0 || predicted.rows() != N || predicted.cols() != n || data.q.rows() != N || data.qd.rows() != N ||
      data.qdd.rows() != N || data.q.cols() != n || data.qd.cols() != n || data.qdd.cols() != n) {
    throw std::invalid_argument("residual analysis: the predictions and samples must have the same non-empty shape");
  }
  if (!(window_seconds > 0.0)) throw std::invalid_argument("residual analysis: the window must be positive");
  const Eigen::MatrixXd r = predicted - data.tau;
  ResidualAnalysis out;
  out.joints.resize(n);
  Eigen::MatrixXd S(N, kResidualSignals);
  for (int k = 0; k < n; ++k) {
    JointResidualSignature& sig = out.joints[k];
    const Eigen::VectorXd rk = r.col(k);
    sig.rms = std::sqrt(rk.squaredNorm() / N);
    const double v_rms = std::sqrt(data.qd.col(k).squaredNorm() / N);
    const double q_mean = data.q.col(k).mean();
    for (int i = 0; i < N; ++i) {
      const double v = data.qd(i, k);
      S(i, kResidualMean) = 1.0;
      S(i, kVelocitySign) = std::abs(v) <= 0.01 * v_rms ? 0.0 : (v > 0 ? 1.0 : -1.0);
      S(i, kVelocity) = v;
      S(i, kAcceleration) = data.qdd(i, k);
      S(i, kPosition) = data.q(i, k) - q_mean;
      S(i, kTorque) = data.tau(i, k);
    }
    // A joint held still: q - mean q is rounding noise, as collinear with the constant as can be.
    const double q_scale = 1.0 + data.q.col(k).cwiseAbs().maxCoeff();
    if (S.col(kPosition).norm() <= 1e-12 * q_scale * std::sqrt(static_cast<double>(N))) S.col(kPosition).setZero();
    // The joint fit without tau: column-scaled, lightly damped normal equations, so a signal that
    // does not vary (a joint at rest) gets a zero coefficient instead of a singular solve.
    constexpr int kFit = kTorque;  // columns 0 .. kPosition
    const auto Sf = S.leftCols(kFit);
    Eigen::VectorXd scale(kFit);
    for (int c = 0; c < kFit; ++c) scale[c] = std::max(Sf.col(c).norm(), 1e-300);
    const Eigen::MatrixXd Sn = Sf * scale.cwiseInverse().asDiagonal();
    Eigen::MatrixXd M = Sn.transpose() * Sn;
    M.diagonal().array() += 1e-9;
    Eigen::VectorXd c = M.ldlt().solve(Sn.transpose() * rk).cwiseQuotient(scale);
    if (!c.allFinite()) c.setZero();
    for (int s = 0; s < kResidualSignals; ++s) {
      sig.coefficients[s] = s < kFit ? c[s] : 0.0;
      sig.alone[s] = s == kResidualMean ? rk.mean() : Slope(rk, S.col(s));
      sig.correlations[s] = s == kResidualMean ? 0.0 : Correlation(rk, S.col(s));
    }
    const double total = rk.squaredNorm();
    sig.explained = total > 0.0 ? std::clamp(1.0 - (rk - Sf * c).squaredNorm() / total, 0.0, 1.0) : 0.0;
  }
  // Windows: consecutive runs of samples spanning window_seconds.
  std::vector<ResidualWindow> windows;
  for (int start = 0; start < N;) {
    int end = start;
    while (end < N && data.t[end] < data.t[start] + window_seconds) ++end;
    if (end == start) ++end;
    const Eigen::MatrixXd block = r.middleRows(start, end - start);
    ResidualWindow w;
    w.t_start = data.t[start];
    w.t_end = data.t[end - 1];
    w.rms = std::sqrt(block.squaredNorm() / block.size());
    Eigen::Index worst = 0;
    block.colwise().squaredNorm().maxCoeff(&worst);
    w.worst_joint = static_cast<int>(worst);
    // A short remainder at the end of the log is not a window of the asked length.
    if (w.t_end - w.t_start >= 0.5 * window_seconds || windows.empty()) windows.push_back(w);
    start = end;
  }
  std::sort(windows.begin(), windows.end(), [](const ResidualWindow& a, const ResidualWindow& b) { return a.rms > b.rms; });
  if (static_cast<int>(windows.size()) > num_windows) windows.resize(std::max(0, num_windows));
  out.worst_windows = windows;
  return out;
}

}  // namespace inertial
