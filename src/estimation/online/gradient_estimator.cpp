#include "inertial/estimation/online/gradient_estimator.hpp"

#include <cmath>
#include <stdexcept>

namespace inertial {

GradientEstimator::GradientEstimator(ParameterLayout layout, int num_measurements, const Eigen::VectorXd& x0,
                                     const Eigen::VectorXd& scale, const GradientOptions& options)
    : RecursiveEstimator(layout.num_features(), num_measurements),
      layout_(std::move(layout)),
      options_(options),
      x_(x0) {
  const int n = layout_.num_parameters();
  if (num_measurements < 1) throw std::invalid_argument("gradient law: needs at least one measurement");
  if (x0.size() != n || !x0.allFinite()) throw std::invalid_argument("gradient law: x0 must be " + std::to_string(n) + " finite numbers");
  if (scale.size() != n || !scale.allFinite() || !(scale.array() > 0).all()) {
    throw std::invalid_argument("gradient law: scale must be " + std::to_string(n) + " positive numbers");
  }
  if (!(options.gain > 0 && options.gain < 2)) throw std::invalid_argument("gradient law: gain must be in (0, 2)");
  if (!(options.measurement_sigma > 0) || !(options.huber > 0) || !(options.gate > 0) || !(options.max_step > 0) ||
      !(options.max_abs_parameter > 0) || options.max_consecutive_outliers < 0) {
    throw std::invalid_argument("gradient law: options must be positive");
  }
  gamma_ = scale.array().square();
  w_.resize(layout_.num_features());
  r_.resize(num_measurements);
  dx_.resize(n);
  H_.resize(num_measurements, n);
}

UpdateStatus GradientEstimator::Apply(const Eigen::MatrixXd& A, const Eigen::VectorXd& y) {
  layout_.Evaluate(x_, A, w_, H_);
  r_ = y;
  r_.noalias() -= A * w_;
  const double sigma = options_.measurement_sigma;
  const double e = r_.norm() / (sigma * std::sqrt(static_cast<double>(r_.size())));
  if (!std::isfinite(e)) return UpdateStatus::kNumerical;
  if (e > options_.gate) {
    if (++consecutive_outliers_ <= options_.max_consecutive_outliers) return UpdateStatus::kOutlier;
    consecutive_outliers_ = 0;
  } else {
    consecutive_outliers_ = 0;
  }
  if (e > options_.huber) r_ *= options_.huber / e;
  const double norm = sigma * sigma + (H_.colwise().squaredNorm().transpose().cwiseProduct(gamma_)).sum();
  dx_.noalias() = H_.transpose() * r_;
  dx_ = (options_.gain / norm) * gamma_.cwiseProduct(dx_);
  if (!dx_.allFinite()) return UpdateStatus::kNumerical;
  const double largest = dx_.lpNorm<Eigen::Infinity>();
  if (largest > options_.max_step) dx_ *= options_.max_step / largest;
  for (int i = 0; i < x_.size(); ++i) {
    if (!(std::abs(x_[i] + dx_[i]) <= options_.max_abs_parameter)) return UpdateStatus::kNumerical;
  }
  x_ += dx_;
  return UpdateStatus::kAccepted;
}

bool GradientEstimator::SetParameters(const Eigen::VectorXd& x, const Eigen::MatrixXd&, std::string*) {
  x_ = x;
  consecutive_outliers_ = 0;  // the run of outliers is not part of a state: a restore starts a fresh one
  return true;
}

}  // namespace inertial
