/// @file linear_rls.hpp
/// The classical baseline: linear recursive least squares directly on the coefficients w (the
/// bodies' pi and the effect coefficients), y = A w, with the same Kalman update, forgetting and
/// robustness as the recursive Gauss-Newton (kalman_update.hpp). Nothing keeps its bodies
/// physically consistent: it is here to measure what consistency costs, and to show the
/// impossible bodies it produces.
#pragma once

#include "inertial/estimation/kalman_update.hpp"
#include "inertial/estimation/recursive_estimator.hpp"

namespace inertial {

class LinearRls final : public RecursiveEstimator {
 public:
  /// @param w0 initial coefficients (e.g. the priors' pi); @param initial_std their uncertainty.
  /// @throws std::invalid_argument for wrong sizes, non-finite w0 or bad options.
  LinearRls(int num_measurements, const Eigen::VectorXd& w0, const Eigen::VectorXd& initial_std,
            const KalmanOptions& options = {});

  std::string_view kind() const override { return "linear_rls"; }
  const Eigen::VectorXd& parameters() const override { return w_; }
  void Coefficients(Eigen::Ref<Eigen::VectorXd> w) const override { w = w_; }
  Eigen::MatrixXd Covariance() const override { return kalman_.Covariance(); }

 protected:
  UpdateStatus Apply(const Eigen::MatrixXd& A, const Eigen::VectorXd& y) override;
  bool SetParameters(const Eigen::VectorXd& x, const Eigen::MatrixXd& P, std::string* why) override;

 private:
  KalmanUpdate kalman_;
  Eigen::VectorXd w_, r_;
};

}  // namespace inertial
