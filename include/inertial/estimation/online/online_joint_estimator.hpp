/// @file online_joint_estimator.hpp
/// The online estimator of a robot from joint-space samples (q, qd, qdd, tau of every DOF, in the
/// model's DOF order): per sample, the features A(q, qd, qdd) of RobotDynamics (joint-torque
/// regressor of every link and rotor, effect features) computed without allocation, then one
/// update of the chosen estimator. A sample whose qdd was not measured (JointSample::qdd_measured
/// false: LCM or CAN streams without accelerations, CSV logs without qdd columns) gives instead the
/// filtered momentum row of momentum_rows.hpp (F[tau] = F[dP/dt + H] w, no qdd, no lag), which
/// feeds the same statistics; its prediction and residual are then those of the filtered torque.
/// The estimators:
///   - gauss_newton (the default): the batch objective's sufficient statistics, re-solved by
///     Gauss-Newton / Levenberg-Marquardt off the tick (online_fit.hpp): the estimate is identify's
///     fit of the samples so far; Solve() runs the solve (when SolveDue(), or from another thread
///     through fit());
///   - ekf: the extended Kalman filter on x (recursive_gauss_newton.hpp), one linearization per
///     sample: kept for comparison and for the single body;
///   - gradient: the gradient law; linear_rls: least squares on pi, the baseline.
/// Update() never allocates and never throws; a bad sample is rejected and counted.
#pragma once

#include <memory>

#include "inertial/estimation/online/gradient_estimator.hpp"
#include "inertial/estimation/online/linear_rls.hpp"
#include "inertial/estimation/online/momentum_rows.hpp"
#include "inertial/estimation/online/online_fit.hpp"
#include "inertial/estimation/online/recursive_gauss_newton.hpp"
#include "inertial/model/joint_samples.hpp"
#include "inertial/model/robot_dynamics.hpp"

namespace inertial {

enum class EstimatorKind { kGaussNewton, kEkf, kGradient, kLinearRls };
/// "gauss_newton", "ekf", "gradient", "linear_rls".
std::string_view ToString(EstimatorKind kind);
/// @throws std::invalid_argument for any other name.
EstimatorKind ParseEstimatorKind(std::string_view name);

struct OnlineEstimatorOptions {
  EstimatorKind kind = EstimatorKind::kGaussNewton;
  double measurement_sigma = 1.0;  ///< per measurement (N m for joint torques, N and N m for wrenches)
  double theta_std = 0.3;          ///< initial uncertainty of every log-Cholesky parameter
  double effect_std = 1.0;         ///< initial uncertainty of every effect parameter (log or linear)
  double linear_std_scale = 0.3;   ///< linear RLS: initial std of each pi entry, relative to |prior| + 0.01
  /// Per-parameter initial uncertainty (for the gradient law, the scale of its effect parameters
  /// only: its bodies move in the log-det metric, and are held by fit.solve.frozen_bodies),
  /// overriding theta_std and effect_std when not empty: e.g. small for links known from CAD, large
  /// for an unknown payload.
  Eigen::VectorXd initial_std;
  KalmanOptions kalman;            ///< measurement_sigma here is overridden by the one above
  OnlineFitOptions fit;            ///< gauss_newton of a robot (measurement_sigma, theta_std, effect_std unused)
  GradientOptions gradient;        ///< measurement_sigma likewise
  /// The corner of the momentum rows' filter for samples without measured qdd (momentum_rows.hpp);
  /// SamplePipeline sets it to the stream's accel_cutoff_hz.
  double momentum_cutoff_hz = 20.0;
};

/// Makes the estimator of `kind` for a model with `layout`, m measurements, starting at x0 (for
/// linear RLS: at w(x0)); gauss_newton here is the extended Kalman filter (a layout has no
/// objective to re-solve: OnlineJointEstimator makes the OnlineFit itself).
/// @throws std::invalid_argument as the constructors.
std::unique_ptr<RecursiveEstimator> MakeRecursiveEstimator(const ParameterLayout& layout, int num_measurements,
                                                           const Eigen::VectorXd& x0,
                                                           const OnlineEstimatorOptions& options);

class OnlineJointEstimator {
 public:
  /// @param x0 RobotDynamics parameters to start from (zeros: the URDF priors, or a batch fit).
  /// @throws std::invalid_argument for a wrong-size x0 or bad options.
  OnlineJointEstimator(RobotDynamics model, const Eigen::VectorXd& x0, const OnlineEstimatorOptions& options = {});

  /// One sample. With qdd measured: the row A(q, qd, qdd), y = tau. Without: the filtered momentum
  /// row; the first such sample (and the first after a sample with qdd, or after a gap longer
  /// than 1 / (2 f_c)) only primes the filter and returns kBuffered (it enters the next row).
  UpdateStatus Update(const JointSample& sample);
  /// Primes the momentum rows' filter with a sample without measured qdd that is not to be
  /// counted (the preprocessing stage's priming sample, refused there): the next sample gives a
  /// row. Nothing else changes. Ignores a sample of wrong size or with a non-finite value.
  void Prime(const JointSample& sample);
  /// Replaces the momentum rows' filter corner (allocates: not per tick); the filter restarts.
  /// @throws std::invalid_argument if cutoff_hz is not positive and finite.
  void SetMomentumCutoff(double cutoff_hz);
  double momentum_cutoff_hz() const { return momentum_.cutoff_hz(); }
  /// gauss_newton: the statistics have grown enough since the last solve (OnlineFit::solve_due);
  /// false for the other estimators, which solve within Update().
  bool SolveDue() const { return fit_ != nullptr && fit_->solve_due(); }
  /// gauss_newton: re-solves the objective now (allocates: off the tick) and takes its estimate,
  /// warm-started or from identify's start (OnlineFit::Solve). Returns false if there was nothing
  /// to solve; the other estimators: false, nothing done.
  bool Solve(bool from_start = false);
  /// gauss_newton solved on another thread: OnlineFit::Adopt of a solution of fit()->Snapshot(),
  /// and the coefficients this adapter keeps follow. False (nothing changed) if not adopted.
  bool Adopt(const OnlineFitSolution& solution);
  /// The OnlineFit of gauss_newton, or null.
  const OnlineFit* fit() const { return fit_; }
  OnlineFit* fit() { return fit_; }
  /// Restores a saved state (RecursiveEstimator::Restore) and the coefficients w(x) this adapter
  /// keeps for coefficients(), Body() (linear RLS) and the next prediction. Returns false (and *why)
  /// without changing anything when the state does not fit.
  bool Restore(const EstimatorState& state, std::string* why);

  const RobotDynamics& model() const { return model_; }
  const RecursiveEstimator& estimator() const { return *estimator_; }
  RecursiveEstimator& estimator() { return *estimator_; }
  EstimatorKind kind() const { return kind_; }
  /// The current coefficients w (every tree body's pi, effect coefficients). Allocation-free.
  const Eigen::VectorXd& coefficients() const { return w_; }
  /// Estimated body e (RobotDynamics::bodies() order) in its report frame. For linear RLS, which
  /// has no per-body parameters, the tree body's pi (payloads merged into their link).
  InertialParams Body(int e) const;
  /// Torques predicted by the current estimate for the last sample given, and its residual
  /// (measured - predicted); zero before the first.
  /// Without measured qdd, both are of the filtered torque F[tau] (momentum_rows.hpp).
  const Eigen::VectorXd& predicted() const { return tau_hat_; }
  const Eigen::VectorXd& residual() const { return residual_; }
  /// For the consumers that compare it with the sample's own features (the stream diagnosis, the
  /// residual channel): the torque's residual by the estimate before the sample. With qdd measured,
  /// residual(); without, the rows' unfiltered midpoint residual u_tau - u w (no lag: momentum_rows.hpp)
  /// low-passed at the momentum cutoff (the stream's accel_cutoff_hz), the filter the preprocessing
  /// stage derives qdd with, so that a candidate's feature of the derived qdd (armature) matches it.
  const Eigen::VectorXd& stream_residual() const { return stream_residual_; }
  /// The features A(q, qd, qdd) of the last sample given when its qdd was measured (its torque's
  /// row); null when that sample gave a momentum row or was refused before its features were
  /// computed. For consumers of the same sample (the payload events), which need not compute them again.
  const Eigen::MatrixXd* torque_features() const { return torque_features_ ? &A_ : nullptr; }

 private:
  RobotDynamics model_;
  EstimatorKind kind_;
  std::unique_ptr<RecursiveEstimator> estimator_;
  OnlineFit* fit_ = nullptr;  ///< estimator_ when it is one
  TreeWorkspace workspace_;
  MomentumRows momentum_;
  Eigen::MatrixXd A_;
  Eigen::VectorXd w_, y_, tau_hat_, residual_, stream_residual_, midpoint_residual_;
  bool torque_features_ = false;  ///< A_ holds the last sample's A(q, qd, qdd)
};

}  // namespace inertial
