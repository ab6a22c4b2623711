#include "inertial/estimation/online/online_joint_estimator.hpp"

#include <cmath>
#include <stdexcept>

#include "inertial/signal/causal_acceleration.hpp"

namespace inertial {

std::string_view ToString(EstimatorKind kind) {
  switch (kind) {
    case EstimatorKind::kGaussNewton: return "gauss_newton";
    case EstimatorKind::kEkf: return "ekf";
    case EstimatorKind::kGradient: return "gradient";
    case EstimatorKind::kLinearRls: return "linear_rls";
  }
  return "unknown";
}

EstimatorKind ParseEstimatorKind(std::string_view name) {
  if (name == "gauss_newton") return EstimatorKind::kGaussNewton;
  if (name == "ekf") return EstimatorKind::kEkf;
  if (name == "gradient") return EstimatorKind::kGradient;
  if (name == "linear_rls") return EstimatorKind::kLinearRls;
  throw std::invalid_argument("unknown estimator '" + std::string(name) + "' (gauss_newton, ekf, gradient, linear_rls)");
}

std::unique_ptr<RecursiveEstimator> MakeRecursiveEstimator(const ParameterLayout& layout, int m,
                                                           const Eigen::VectorXd& x0,
                                                           const OnlineEstimatorOptions& options) {
  if (x0.size() != layout.num_parameters()) {
    throw std::invalid_argument("online estimator: x0 has " + std::to_string(x0.size()) + " entries, the model " +
                                std::to_string(layout.num_parameters()));
  }
  Eigen::VectorXd std_x(layout.num_parameters());
  std_x.setConstant(options.effect_std);
  for (const BodyBlock& b : layout.bodies()) std_x.segment<10>(b.parameter).setConstant(options.theta_std);
  if (options.initial_std.size() != 0) {
    if (options.initial_std.size() != layout.num_parameters()) {
      throw std::invalid_argument("online estimator: initial_std has " + std::to_string(options.initial_std.size()) +
                                  " entries, the model " + std::to_string(layout.num_parameters()));
    }
    std_x = options.initial_std;
  }
  // One body measured by its wrench: the fixed-size estimators (same algorithm, compile-time sizes).
  const bool one_body = layout.bodies().size() == 1 && layout.scalars().empty() && layout.num_features() == 10 && m == 6;
  switch (options.kind) {
    case EstimatorKind::kGaussNewton:
    case EstimatorKind::kEkf: {
      RecursiveGaussNewtonOptions o;
      o.kalman = options.kalman;
      o.kalman.measurement_sigma = options.measurement_sigma;
      if (one_body) return std::make_unique<BodyGaussNewton>(layout, m, x0, std_x, o);
      return std::make_unique<RecursiveGaussNewton>(layout, m, x0, std_x, o);
    }
    case EstimatorKind::kGradient: {
      GradientOptions o = options.gradient;
      o.measurement_sigma = options.measurement_sigma;
      // The bodies the online fit's solve holds at their priors, the law holds too.
      if (o.frozen_bodies.empty() && options.fit.solve.frozen_bodies.size() == layout.bodies().size()) {
        o.frozen_bodies = options.fit.solve.frozen_bodies;
      }
      return std::make_unique<GradientEstimator>(layout, m, x0, std_x, o);
    }
    case EstimatorKind::kLinearRls: {
      Eigen::VectorXd w0(layout.num_features());
      layout.Coefficients(x0, w0);
      const Eigen::VectorXd std_w = (options.linear_std_scale * (w0.cwiseAbs().array() + 0.01)).matrix();
      KalmanOptions o = options.kalman;
      o.measurement_sigma = options.measurement_sigma;
      o.max_step = std::numeric_limits<double>::infinity();
      if (one_body) return std::make_unique<BodyLinearRls>(m, w0, std_w, o);
      return std::make_unique<LinearRls>(m, w0, std_w, o);
    }
  }
  throw std::invalid_argument("online estimator: unknown kind");
}

OnlineJointEstimator::OnlineJointEstimator(RobotDynamics model, const Eigen::VectorXd& x0,
                                           const OnlineEstimatorOptions& options)
    : model_(std::move(model)), kind_(options.kind), momentum_(model_, options.momentum_cutoff_hz) {
  if (options.kind == EstimatorKind::kGaussNewton) {
    auto fit = std::make_unique<OnlineFit>(model_, x0, options.fit);
    fit_ = fit.get();
    estimator_ = std::move(fit);
  } else {
    estimator_ = MakeRecursiveEstimator(ParameterLayout::FromRobot(model_), model_.num_dofs(), x0, options);
  }
  workspace_ = model_.MakeWorkspace();
  A_.resize(model_.num_dofs(), model_.num_features());
  w_.resize(model_.num_features());
  y_.resize(model_.num_dofs());
  stream_residual_ = Eigen::VectorXd::Zero(model_.num_dofs());
  midpoint_residual_ = Eigen::VectorXd::Zero(model_.num_dofs());
  estimator_->Coefficients(w_);
  tau_hat_ = Eigen::VectorXd::Zero(model_.num_dofs());
  residual_ = Eigen::VectorXd::Zero(model_.num_dofs());
}

UpdateStatus OnlineJointEstimator::Update(const JointSample& s) {
  const int n = model_.num_dofs();
  UpdateStatus status = UpdateStatus::kAccepted;
  const bool momentum = !s.qdd_measured;
  torque_features_ = false;
  if (s.q.size() != n || s.qd.size() != n || (!momentum && s.qdd.size() != n) || s.tau.size() != n) {
    status = UpdateStatus::kWrongSize;
  } else if (!s.q.allFinite() || !s.qd.allFinite() || (!momentum && !s.qdd.allFinite()) || !std::isfinite(s.t)) {
    status = UpdateStatus::kNonFinite;  // the features of a non-finite state would be garbage
  } else if (momentum && momentum_.primed() && !(s.t > momentum_.last_time())) {
    status = UpdateStatus::kOutOfOrder;  // the filter differences in time
  }
  if (status != UpdateStatus::kAccepted) {
    estimator_->CountSample(status);
    return status;
  }
  if (momentum) {
    // A non-finite torque reaches the estimator's own check below through y; the filter would
    // carry it on, so it is not fed to the filter.
    if (!s.tau.allFinite()) {
      estimator_->CountSample(UpdateStatus::kNonFinite);
      return UpdateStatus::kNonFinite;
    }
    if (!momentum_.Update(model_, s.t, s.q, s.qd, s.tau, A_, y_)) {
      stream_residual_.setZero();  // the filters restart
      estimator_->CountSample(UpdateStatus::kBuffered);
      return UpdateStatus::kBuffered;
    }
    midpoint_residual_ = momentum_.midpoint_torque();
    midpoint_residual_.noalias() -= momentum_.midpoint_row() * w_;
    // Low-passed exactly as the preprocessing stage filters the derived qdd (causal_acceleration.hpp).
    const double alpha = CausalLowPassGain(momentum_.last_step(), momentum_.cutoff_hz());
    stream_residual_ += alpha * (midpoint_residual_ - stream_residual_);
  } else {
    momentum_.Reset();  // rows without qdd start again after a sample with it
    model_.Features(s.q, s.qd, s.qdd, &workspace_, A_);
    torque_features_ = true;
    y_ = s.tau;
  }
  tau_hat_.noalias() = A_ * w_;
  residual_ = y_ - tau_hat_;
  if (!momentum) stream_residual_ = residual_;
  status = estimator_->Update(s.t, A_, y_);
  if (status == UpdateStatus::kAccepted) estimator_->Coefficients(w_);
  return status;
}

void OnlineJointEstimator::Prime(const JointSample& s) {
  const int n = model_.num_dofs();
  if (s.q.size() != n || s.qd.size() != n || s.tau.size() != n || !s.q.allFinite() || !s.qd.allFinite() ||
      !s.tau.allFinite() || !std::isfinite(s.t)) {
    return;
  }
  momentum_.Reset();
  stream_residual_.setZero();
  momentum_.Update(model_, s.t, s.q, s.qd, s.tau, A_, y_);
}

void OnlineJointEstimator::SetMomentumCutoff(double cutoff_hz) { momentum_ = MomentumRows(model_, cutoff_hz); }

bool OnlineJointEstimator::Solve(bool from_start) {
  if (fit_ == nullptr || !fit_->Solve(from_start)) return false;
  estimator_->Coefficients(w_);
  return true;
}

bool OnlineJointEstimator::Adopt(const OnlineFitSolution& solution) {
  if (fit_ == nullptr || !fit_->Adopt(solution)) return false;
  estimator_->Coefficients(w_);
  return true;
}

bool OnlineJointEstimator::Restore(const EstimatorState& state, std::string* why) {
  if (!estimator_->Restore(state, why)) return false;
  estimator_->Coefficients(w_);
  return true;
}

InertialParams OnlineJointEstimator::Body(int e) const {
  if (kind_ == EstimatorKind::kLinearRls) {
    return InertialParams::FromVector(w_.segment<10>(10 * model_.bodies().at(e).block));
  }
  return model_.BodyInertia(e, estimator_->parameters());
}


}  // namespace inertial
