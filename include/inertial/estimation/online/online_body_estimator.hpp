/// @file online_body_estimator.hpp
/// The online estimator of one rigid body (a payload on a force/torque sensor, a link with a
/// wrench sensor) from body-frame samples: twist xi = [omega; v], applied wrench w = [moment;
/// force] (what the sensor exerts on the body), optionally gravity g_B in the body frame, and
/// either the twist's derivative (then w = Y(xi, xi_dot, g) pi, eq. 12) or nothing (then pairs of
/// successive samples by the paper's implicit midpoint rule, eq. 13). m = 6 measurements, 10
/// log-Cholesky parameters relative to a prior body; Gauss-Newton and linear RLS run at compile-time
/// sizes (BodyGaussNewton, BodyLinearRls). Update() never allocates and never throws.
#pragma once

#include <memory>

#include "inertial/estimation/online/online_joint_estimator.hpp"
#include "inertial/model/body_sample.hpp"

namespace inertial {


class OnlineBodyEstimator {
 public:
  /// @throws std::invalid_argument if the prior is not fully physically consistent or options are bad.
  OnlineBodyEstimator(const InertialParams& prior, const OnlineEstimatorOptions& options = {});

  /// kBuffered for the first sample of a pair (samples without acceleration).
  UpdateStatus Update(const BodySample& sample);

  /// Restores the estimator from a checkpoint (RecursiveEstimator::Restore) and drops a held twist:
  /// a pair never spans a restore, since the samples before a checkpoint and after it are not known
  /// to be consecutive; the next sample without acceleration starts a new pair.
  bool Restore(const EstimatorState& state, std::string* why);

  InertialParams Body() const;
  const RecursiveEstimator& estimator() const { return *estimator_; }
  RecursiveEstimator& estimator() { return *estimator_; }
  const ParameterLayout& layout() const { return layout_; }

 private:
  UpdateStatus Use(double t, const Matrix6x10& A, const Vector6& y);
  ParameterLayout layout_;
  EstimatorKind kind_;
  std::unique_ptr<RecursiveEstimator> estimator_;
  // The same estimator when it is of fixed size (Gauss-Newton, linear RLS), else null.
  BodyGaussNewton* body_gauss_newton_ = nullptr;
  BodyLinearRls* body_linear_rls_ = nullptr;
  Eigen::MatrixXd A_;
  Eigen::VectorXd y_, w_;
  bool has_previous_ = false;
  BodySample previous_;
};

}  // namespace inertial
