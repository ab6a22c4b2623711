/// @file recursive_gauss_newton.hpp
/// Recursive Gauss-Newton on log-Cholesky parameters: every sample linearizes y = A w(x) at the
/// current x (H = A J_w_x, block by block, parameter_layout.hpp) and takes the Kalman measurement
/// update of kalman_update.hpp (an extended Kalman filter on x with a static parameter model).
/// Because x is theta relative to each body's prior (eq. 11) plus exp-parameterized coefficients,
/// every estimate at every tick is a fully physically consistent body with plausible effects,
/// whatever the data do. Cost per sample O(n^2 m) plus the features.
/// Allocation-free and exception-free after construction.
#pragma once

#include "inertial/estimation/online/kalman_update.hpp"
#include "inertial/estimation/parameter_layout.hpp"
#include "inertial/estimation/online/recursive_estimator.hpp"

namespace inertial {

struct RecursiveGaussNewtonOptions {
  KalmanOptions kalman;
  /// A step that would take any |x_i| beyond this is refused (kNumerical): theta this large means
  /// density scalings of e^100, far outside any real body.
  double max_abs_parameter = 50.0;
  /// For samples beyond the Huber threshold (large innovations, where the linearization may be
  /// poor): where the step raises the sample's residual, it is halved up to this many times.
  int max_halvings = 4;
};

/// N parameters, M measurements, F features: Eigen::Dynamic for all three (any layout), or one
/// body's 10, 6, 10 (BodyGaussNewton: fixed-size products throughout, and a typed Update()).
template <int N, int M, int F>
class BasicRecursiveGaussNewton final : public RecursiveEstimator {
 public:
  using MatrixA = Eigen::Matrix<double, M, F>;
  using VectorM = Eigen::Matrix<double, M, 1>;
  static constexpr bool kDynamic = N == Eigen::Dynamic;

  /// @param x0 initial parameters (e.g. zeros: the priors; or a batch fit);
  /// @param initial_std standard deviation of each parameter's initial uncertainty.
  /// @throws std::invalid_argument for wrong sizes (of a fixed-size estimator: a layout that is not
  /// one body), non-finite x0 or bad options.
  BasicRecursiveGaussNewton(ParameterLayout layout, int num_measurements, const Eigen::VectorXd& x0,
                            const Eigen::VectorXd& initial_std, const RecursiveGaussNewtonOptions& options = {});

  using RecursiveEstimator::Update;
  /// The same as Update(t, A, y) with the estimator's own types (for fixed sizes: no copies).
  UpdateStatus Update(double t, const MatrixA& A, const VectorM& y);

  /// "ekf" for a robot's layout, "gauss_newton" for the fixed-size single body (its default estimator).
  std::string_view kind() const override { return kDynamic ? "ekf" : "gauss_newton"; }
  const Eigen::VectorXd& parameters() const override { return x_; }
  void Coefficients(Eigen::Ref<Eigen::VectorXd> w) const override { layout_.Coefficients(x_, w); }
  Eigen::MatrixXd Covariance() const override { return kalman_.Covariance(); }
  std::uint64_t changes_detected() const override { return kalman_.changes_detected(); }
  const ParameterLayout& layout() const { return layout_; }
  /// sqrt(d^2/m) of the last sample's innovation, in measurement sigmas.
  double normalized_innovation() const { return kalman_.normalized_innovation(); }

 protected:
  UpdateStatus Apply(const Eigen::MatrixXd& A, const Eigen::VectorXd& y) override;
  bool SetParameters(const Eigen::VectorXd& x, const Eigen::MatrixXd& P, std::string* why) override;

 private:
  UpdateStatus Step(const MatrixA& A, const VectorM& y);
  void Evaluate(const MatrixA& A);  // w_ and H_ at x_
  void CoefficientsAt(const Eigen::Matrix<double, N, 1>& x);  // w_ at x
  ParameterLayout layout_;
  RecursiveGaussNewtonOptions options_;
  BasicKalmanUpdate<N, M> kalman_;
  Eigen::VectorXd x_;
  Eigen::Matrix<double, N, 1> x_trial_;  // fixed for the body: the step's arithmetic unrolled
  Eigen::Matrix<double, F, 1> w_;
  VectorM r_;
  Eigen::Matrix<double, M, N> H_;
};

using RecursiveGaussNewton = BasicRecursiveGaussNewton<Eigen::Dynamic, Eigen::Dynamic, Eigen::Dynamic>;
/// One body (ParameterLayout::SingleBody) and its 6-component wrench.
using BodyGaussNewton = BasicRecursiveGaussNewton<10, 6, 10>;
extern template class BasicRecursiveGaussNewton<Eigen::Dynamic, Eigen::Dynamic, Eigen::Dynamic>;
extern template class BasicRecursiveGaussNewton<10, 6, 10>;

}  // namespace inertial
