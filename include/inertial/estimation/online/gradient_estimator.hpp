/// @file gradient_estimator.hpp
/// A normalized gradient (adaptive) law on log-Cholesky parameters, for the tightest loops: with
/// H = A J_w_x at the current x (parameter_layout.hpp) and r = y - A w(x),
///
///   dx = gain * Gamma H^T r / (sigma^2 + sum_j Gamma_j |H_:j|^2),
///
/// Gamma = diag(scale^2) (the relative speed of each parameter). Normalizing by the regressor's
/// size keeps the law stable for 0 < gain < 2 whatever the excitation (a normalized LMS). Cost
/// O(n m) per sample plus the features: no covariance. Every x is a consistent body. Outliers are
/// gated on |r| / (sigma sqrt(m)) as in the Kalman update; steps are bounded.
/// Allocation-free and exception-free after construction.
#pragma once

#include "inertial/estimation/parameter_layout.hpp"
#include "inertial/estimation/online/recursive_estimator.hpp"

namespace inertial {

struct GradientOptions {
  /// Normalized step, in (0, 2). The steady-state error grows with it (gain 1 fits each noisy
  /// sample exactly); 0.05 suits torque data with noise of a tenth of the signal.
  double gain = 0.05;
  double measurement_sigma = 1.0;  ///< standard deviation of each measurement
  double huber = 3.0;              ///< normalized residual (sigmas) where down-weighting starts
  double gate = 30.0;              ///< normalized residual (sigmas) beyond which a sample is an outlier
  int max_consecutive_outliers = 50;
  double max_step = 0.1;           ///< bound on |dx|_inf per sample
  double max_abs_parameter = 50.0;
};

class GradientEstimator final : public RecursiveEstimator {
 public:
  /// @param scale per-parameter adaptation scale (Gamma = diag(scale^2)), positive.
  /// @throws std::invalid_argument for wrong sizes, non-finite values or bad options.
  GradientEstimator(ParameterLayout layout, int num_measurements, const Eigen::VectorXd& x0,
                    const Eigen::VectorXd& scale, const GradientOptions& options = {});

  std::string_view kind() const override { return "gradient"; }
  const Eigen::VectorXd& parameters() const override { return x_; }
  void Coefficients(Eigen::Ref<Eigen::VectorXd> w) const override { layout_.Coefficients(x_, w); }
  Eigen::MatrixXd Covariance() const override { return Eigen::MatrixXd(); }
  const ParameterLayout& layout() const { return layout_; }

 protected:
  UpdateStatus Apply(const Eigen::MatrixXd& A, const Eigen::VectorXd& y) override;
  bool SetParameters(const Eigen::VectorXd& x, const Eigen::MatrixXd& P, std::string* why) override;

 private:
  ParameterLayout layout_;
  GradientOptions options_;
  Eigen::VectorXd x_, gamma_, w_, r_, dx_;
  Eigen::MatrixXd H_;
  int consecutive_outliers_ = 0;
};

}  // namespace inertial
