#include "inertial/estimation/online/recursive_gauss_newton.hpp"

#include <cmath>
#include <stdexcept>

namespace inertial {

template <int N, int M, int F>
BasicRecursiveGaussNewton<N, M, F>::BasicRecursiveGaussNewton(ParameterLayout layout, int num_measurements,
                                                              const Eigen::VectorXd& x0,
                                                              const Eigen::VectorXd& initial_std,
                                                              const RecursiveGaussNewtonOptions& options)
    : RecursiveEstimator(layout.num_features(), num_measurements),
      layout_(std::move(layout)),
      options_(options),
      kalman_(layout_.num_parameters(), num_measurements, initial_std, options.kalman),
      x_(x0) {
  if (!kDynamic && (layout_.bodies().size() != 1 || !layout_.scalars().empty() || layout_.num_features() != F)) {
    throw std::invalid_argument("recursive Gauss-Newton: the fixed-size estimator is for one body's layout");
  }
  if (x0.size() != layout_.num_parameters() || !x0.allFinite()) {
    throw std::invalid_argument("recursive Gauss-Newton: x0 must be " + std::to_string(layout_.num_parameters()) +
                                " finite numbers");
  }
  if (!(options.max_abs_parameter > 0)) throw std::invalid_argument("recursive Gauss-Newton: max_abs_parameter must be positive");
  w_.resize(layout_.num_features());
  x_trial_.resize(layout_.num_parameters());
  r_.resize(num_measurements);
  H_.resize(num_measurements, layout_.num_parameters());
}

template <int N, int M, int F>
UpdateStatus BasicRecursiveGaussNewton<N, M, F>::Update(double t, const MatrixA& A, const VectorM& y) {
  const bool sizes_ok = A.rows() == num_measurements() && A.cols() == num_features() && y.size() == num_measurements();
  return Admit(t, sizes_ok, sizes_ok && A.allFinite() && y.allFinite(), [&] { return Step(A, y); });
}

template <int N, int M, int F>
UpdateStatus BasicRecursiveGaussNewton<N, M, F>::Apply(const Eigen::MatrixXd& A, const Eigen::VectorXd& y) {
  if constexpr (kDynamic) {
    return Step(A, y);
  } else {
    return Step(MatrixA(A), VectorM(y));
  }
}

template <int N, int M, int F>
void BasicRecursiveGaussNewton<N, M, F>::Evaluate(const MatrixA& A) {
  if constexpr (kDynamic) {
    layout_.Evaluate(x_, A, w_, H_);
  } else {
    // H = A J from J's structure (log_cholesky.hpp), without forming J.
    w_ = layout_.bodies()[0].map.ToPiProjected(x_.template head<10>(), A, &H_);
  }
}

template <int N, int M, int F>
void BasicRecursiveGaussNewton<N, M, F>::CoefficientsAt(const Eigen::Matrix<double, N, 1>& x) {
  if constexpr (kDynamic) {
    layout_.Coefficients(x, w_);
  } else {
    w_ = layout_.bodies()[0].map.ToPi(x.template head<10>());
  }
}

template <int N, int M, int F>
UpdateStatus BasicRecursiveGaussNewton<N, M, F>::Step(const MatrixA& A, const VectorM& y) {
  Evaluate(A);
  if constexpr (kDynamic) {
    r_ = y;
    r_.noalias() -= A * w_;
  } else {
    r_ = y - 0.5 * H_.col(theta_index::kAlpha);  // H's alpha column is 2 A pi (ToPiProjected)
  }
  const UpdateStatus status = kalman_.Step(H_, r_);
  if (status != UpdateStatus::kAccepted) return status;
  const auto& dx = kalman_.step();
  // Damping: the linearization can be poor far from the estimate (a large innovation, a changed
  // payload). The Kalman step of a linear model always lowers this sample's residual; where the
  // true model's residual does not fall, the step is halved (up to max_halvings times).
  // An ordinary sample (innovation within the Huber threshold) is taken as is: its linearization
  // error is second order in a step that small, and the check would cost a third of the tick.
  const double before = r_.squaredNorm();
  double scale = 1.0;
  const bool check = kalman_.normalized_innovation() > options_.kalman.huber;
  x_trial_ = x_ + dx;
  for (int k = 0; check && k <= options_.max_halvings; ++k) {
    x_trial_ = x_ + scale * dx;
    CoefficientsAt(x_trial_);
    r_ = y;
    r_.noalias() -= A * w_;
    if (r_.squaredNorm() <= before || k == options_.max_halvings) break;  // the last try is taken
    scale *= 0.5;
  }
  // (NaN compares false: refused too.)
  if (!(x_trial_.array().abs() <= options_.max_abs_parameter).all()) return UpdateStatus::kNumerical;
  x_ = x_trial_;
  kalman_.Commit(scale);
  return UpdateStatus::kAccepted;
}

template <int N, int M, int F>
bool BasicRecursiveGaussNewton<N, M, F>::SetParameters(const Eigen::VectorXd& x, const Eigen::MatrixXd& P,
                                                       std::string* why) {
  if (!kalman_.SetCovariance(P)) {
    if (why != nullptr) *why = "the covariance is missing, of the wrong size or not finite";
    return false;
  }
  x_ = x;
  return true;
}

template class BasicRecursiveGaussNewton<Eigen::Dynamic, Eigen::Dynamic, Eigen::Dynamic>;
template class BasicRecursiveGaussNewton<10, 6, 10>;

}  // namespace inertial
