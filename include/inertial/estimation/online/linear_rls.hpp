/// @file linear_rls.hpp
/// The classical baseline: linear recursive least squares directly on the coefficients w (the
/// bodies' pi and the effect coefficients), y = A w, with the same Kalman update, forgetting and
/// robustness as the recursive Gauss-Newton (kalman_update.hpp). Nothing keeps its bodies
/// physically consistent: it is here to measure what consistency costs, and to show the
/// impossible bodies it produces.
#pragma once

#include "inertial/estimation/online/kalman_update.hpp"
#include "inertial/estimation/online/recursive_estimator.hpp"

namespace inertial {

/// M measurements, F coefficients: Eigen::Dynamic for both, or one body's 6 and 10 (BodyLinearRls:
/// fixed-size products and a typed Update(), so that the baseline is as fast as the fixed-size
/// Gauss-Newton it is compared with).
template <int M, int F>
class BasicLinearRls final : public RecursiveEstimator {
 public:
  using MatrixA = Eigen::Matrix<double, M, F>;
  using VectorM = Eigen::Matrix<double, M, 1>;

  /// @param w0 initial coefficients (e.g. the priors' pi); @param initial_std their uncertainty.
  /// @throws std::invalid_argument for wrong sizes, non-finite w0 or bad options.
  BasicLinearRls(int num_measurements, const Eigen::VectorXd& w0, const Eigen::VectorXd& initial_std,
                 const KalmanOptions& options = {});

  using RecursiveEstimator::Update;
  /// The same as Update(t, A, y) with the estimator's own types (for fixed sizes: no copies).
  UpdateStatus Update(double t, const MatrixA& A, const VectorM& y);

  std::string_view kind() const override { return "linear_rls"; }
  const Eigen::VectorXd& parameters() const override { return w_; }
  void Coefficients(Eigen::Ref<Eigen::VectorXd> w) const override { w = w_; }
  Eigen::MatrixXd Covariance() const override { return kalman_.Covariance(); }

 protected:
  UpdateStatus Apply(const Eigen::MatrixXd& A, const Eigen::VectorXd& y) override;
  bool SetParameters(const Eigen::VectorXd& x, const Eigen::MatrixXd& P, std::string* why) override;

 private:
  UpdateStatus Step(const MatrixA& A, const VectorM& y);
  BasicKalmanUpdate<F, M> kalman_;
  Eigen::VectorXd w_;
  VectorM r_;
};

using LinearRls = BasicLinearRls<Eigen::Dynamic, Eigen::Dynamic>;
/// One body's 10 coefficients pi and its 6-component wrench.
using BodyLinearRls = BasicLinearRls<6, 10>;
extern template class BasicLinearRls<Eigen::Dynamic, Eigen::Dynamic>;
extern template class BasicLinearRls<6, 10>;

}  // namespace inertial
