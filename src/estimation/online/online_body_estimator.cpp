#include "inertial/estimation/online/online_body_estimator.hpp"

#include <cmath>

#include "inertial/model/midpoint_regression.hpp"
#include "inertial/model/rigid_body_regressor.hpp"

namespace inertial {

OnlineBodyEstimator::OnlineBodyEstimator(const InertialParams& prior, const OnlineEstimatorOptions& options)
    : layout_(ParameterLayout::SingleBody(prior)), kind_(options.kind) {
  estimator_ = MakeRecursiveEstimator(layout_, 6, Eigen::VectorXd::Zero(10), options);
  body_gauss_newton_ = dynamic_cast<BodyGaussNewton*>(estimator_.get());
  body_linear_rls_ = dynamic_cast<BodyLinearRls*>(estimator_.get());
  A_.resize(6, 10);
  y_.resize(6);
  w_.resize(10);
}

UpdateStatus OnlineBodyEstimator::Update(const BodySample& s) {
  const bool finite = std::isfinite(s.t) && s.twist.allFinite() && s.wrench.allFinite() && s.gravity.allFinite() &&
                      (!s.has_acceleration || s.acceleration.allFinite());
  if (!finite) {
    estimator_->CountSample(UpdateStatus::kNonFinite);
    return UpdateStatus::kNonFinite;
  }
  // Time strictly increasing over every sample given, a held twist included (its time is the
  // latest one when it came after the estimator's last): checked before a twist is held or paired,
  // so that a refused sample never becomes half of a pair.
  const bool after_estimator = !estimator_->has_time() || s.t > estimator_->last_time();
  const bool after_held = !has_previous_ || s.t > previous_.t;
  if (!after_estimator || !after_held) {
    estimator_->CountSample(UpdateStatus::kOutOfOrder);
    return UpdateStatus::kOutOfOrder;
  }
  if (s.has_acceleration) return Use(s.t, RigidBodyRegressor(s.twist, s.acceleration, s.gravity), s.wrench);
  if (!has_previous_) {
    previous_ = s;
    has_previous_ = true;
    estimator_->CountSample(UpdateStatus::kBuffered);
    return UpdateStatus::kBuffered;
  }
  const TwistWrenchSample a{previous_.t, previous_.twist, previous_.wrench}, b{s.t, s.twist, s.wrench};
  Matrix6x10 Y;
  Vector6 w;
  // Gravity of the pair: the mean of the two samples' body-frame gravity.
  MidpointRegressorPair(a, b, 0.5 * (previous_.gravity + s.gravity), &Y, &w);
  previous_ = s;
  return Use(s.t, Y, w);
}

UpdateStatus OnlineBodyEstimator::Use(double t, const Matrix6x10& A, const Vector6& y) {
  // The fixed-size estimators take the sample as it is; the others as dynamic-size copies.
  if (body_gauss_newton_ != nullptr) return body_gauss_newton_->Update(t, A, y);
  if (body_linear_rls_ != nullptr) return body_linear_rls_->Update(t, A, y);
  A_ = A;
  y_ = y;
  return estimator_->Update(t, A_, y_);
}

InertialParams OnlineBodyEstimator::Body() const {
  if (kind_ == EstimatorKind::kLinearRls) return InertialParams::FromVector(estimator_->parameters().head<10>());
  return layout_.Body(0, estimator_->parameters());
}

bool OnlineBodyEstimator::Restore(const EstimatorState& state, std::string* why) {
  if (!estimator_->Restore(state, why)) return false;
  has_previous_ = false;
  return true;
}

}  // namespace inertial
