/// @file excitation_monitor.hpp
/// Which physical quantities a joint-space stream determines, and which it leaves to the prior,
/// over a sliding window and since start (issue 19): "thigh.m and shank.cz are not excited in the
/// last 10 s".
///
/// Method. The stream is modelled as the online estimators see it (online_joint_estimator.hpp):
/// tau = A(q, qd, qdd) w(x) + noise, with independent Gaussian torque noise of std sigma_i on
/// channel (DOF) i, and a Gaussian prior x ~ N(x_prior, P0) (P0: the estimator's initial
/// covariance). The information the samples carry about the coefficients w is
///
///   F_w = sum_samples weight A^T S^-2 A,      S = diag(sigma)              [1 / (N m)^2 scaled by w's units]
///
/// which depends on the data only (not on x, not on the torques): Add() accumulates it, once since
/// start and over a window. Linearizing w(x) at the current estimate x (J_w_x of
/// RobotDynamics::Coefficients), the posterior covariance of x given the prior and the samples is
///
///   Post = (P0^-1 + J^T F_w J)^-1.
///
/// For a scalar physical quantity phi(x) with gradient g = dphi/dx, its posterior and prior variances
/// are g^T Post g and g^T P0 g, and
///
///   ratio = g^T Post g / g^T P0 g   in (0, 1]
///
/// is the fraction of the prior's variance the data leave. It does not depend on phi's units or
/// scale (g enters above and below), nor on the parameterization of x to first order, nor on how
/// the torque channels are scaled if sigma is right. For one scalar Gaussian quantity with prior
/// information I_0 and data information I_d, ratio = I_0 / (I_0 + I_d).
///
/// Threshold: a quantity is "excited" (the stream determines it) when ratio <= kExcitedVarianceRatio
/// = 0.25, i.e. its posterior std is at most half its prior std, equivalently (scalar case) the
/// data carry at least three times the prior's information about it: the estimate is then mostly
/// the data's, not the prior's. Not 0.5 (data and prior equal, the line fit_uncertainty.hpp draws
/// for "held by the prior"): the ratio also counts what the prior's correlations pass on. The
/// log-Cholesky alpha scales a body's mass and all its inertia together, so data that fix some of
/// a body's quantities lower the ratio of others no torque separates. Measured on the bundled leg
/// with the knee at rest (tests/diagnosis/excitation_monitor_test.cpp): the shank's mass, which the
/// torques then see only in sums that the thigh's free parameters absorb, falls to 0.25 in the
/// window without rotors, 0.51 with them; the shank's Ixx to 0.46. No threshold separates such
/// quantities exactly, and 0.25 sits at the edge of the worst case measured (the finer test is the
/// split of the posterior variance into the data's and the prior's shares, fit_uncertainty.hpp).
/// Conversely a COM coordinate c = h / m comes out excited when the data fix h even if not m: the
/// prior's COM std (0.3 m for theta std 0.3) dwarfs |c| times m's relative std.
/// The decision is relative to P0: it answers "has the stream taught us this beyond what we
/// assumed", so a tighter prior needs more data to call a quantity excited.
///
/// Quantities. For every estimated body (RobotDynamics::bodies() order), in its report frame
/// (EstimatedBody::report_frame, as RobotDynamics::BodyInertia): m [kg], cx, cy, cz (COM = h / m,
/// [m]), and the rotational inertia about the COM Ixx, Iyy, Izz, Ixy, Iyz, Ixz [kg m^2] (I_C = I_O -
/// (|h|^2 1 - h h^T) / m, Ixy the (0,1) tensor entry; MassComInertiaAboutCom, parameter_layout.hpp).
/// For every effect term, each of RobotDynamics::EffectValues: b, bc, c, Ia, {k, q0}, {bp, bn}, p1.
/// Names: "<body>.<quantity>" ("thigh.m", "rotor@knee.Izz") and "<kind>@<joint>.<value>"
/// ("viscous@knee.b").
///
/// Window. Time is cut into blocks of window / num_blocks seconds from the first sample; the
/// information of each block is summed while it is current, then kept in a ring of num_blocks
/// closed blocks, and the oldest is dropped as a new one closes. The window is the current block
/// plus the num_blocks closed blocks before it: it covers between window and window + one block of
/// the latest time (less at the start), so "not excited in the last 10 s" is never said of data
/// shorter than 10 s. Since start is every closed block plus the current one. Memory is
/// (num_blocks + 2) F x F doubles, allocated at construction.
///
/// Decimation. Samples may be given sparsely (every k-th sample of the stream, to save time): give
/// weight = k, and the information counts each given sample for the k it stands for, close to the
/// full stream's when the features change little over k samples. With weight 1 the information
/// counts only the samples given, which understates it and makes fewer quantities "excited" (the
/// ratios are not scale-free in the information: more data, smaller ratios).
///
/// Real time. Add() allocates nothing and throws nothing (tests/diagnosis/excitation_monitor_test.cpp
/// counts every heap allocation around it); Evaluate() allocates and is meant for a slower thread
/// every few seconds: a controller copies the information with CopyInformation() (allocation-free
/// into a buffer from MakeInformation()) under its own lock and evaluates the copy elsewhere.
/// The class is not thread-safe by itself.
///
/// Conventions: SI units; torques in N m (forces in N for prismatic joints); time in seconds; pi,
/// theta and mci orders of types.hpp and parameter_layout.hpp.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "inertial/signal/update_status.hpp"
#include "inertial/model/robot_dynamics.hpp"

namespace inertial {

/// The largest ratio of posterior to prior variance at which a quantity counts as excited: posterior
/// std at most half the prior std, the data holding at least three quarters of the information
/// about it (see the file comment for why 0.25 and not 0.5).
inline constexpr double kExcitedVarianceRatio = 0.25;

/// The window and the threshold of an ExcitationMonitor.
struct ExcitationOptions {
  double window_seconds = 10.0;  ///< nominal window length [s], > 0
  int num_blocks = 10;           ///< blocks of window_seconds / num_blocks [s] each, >= 1
  double excited_ratio = kExcitedVarianceRatio;  ///< threshold on the variance ratio, in (0, 1)
};

/// The information accumulated so far, as a full symmetric copy (see the file comment): what a
/// real-time thread hands to the thread that evaluates it.
struct ExcitationInformation {
  Eigen::MatrixXd window;       ///< F_w over the window (F x F, full symmetric)
  Eigen::MatrixXd since_start;  ///< F_w since start (F x F, full symmetric)
  double window_seconds = 0.0;       ///< time the window covers, from its oldest block's start to the last sample [s]
  double since_start_seconds = 0.0;  ///< from the first sample to the last [s]
  double window_weight = 0.0;        ///< sum of the weights of the window's samples (the samples they stand for)
  double since_start_weight = 0.0;   ///< likewise since start
};

/// How much the stream determines one physical quantity (see the file comment).
struct QuantityExcitation {
  std::string name;   ///< "thigh.m", "shank.cz", "viscous@knee.b"
  std::string group;  ///< the body or effect term it belongs to: "thigh", "viscous@knee"
  double ratio_window = 1.0;       ///< posterior / prior variance given the window's samples, (0, 1]
  double ratio_since_start = 1.0;  ///< the same given every sample since start, <= ratio_window
  bool excited_window = false;       ///< ratio_window <= the threshold
  bool excited_since_start = false;  ///< ratio_since_start <= the threshold
};

/// Every quantity's excitation at one evaluation, and what it was computed from.
struct ExcitationReport {
  double nominal_window_seconds = 0.0;  ///< ExcitationOptions::window_seconds [s]
  double window_seconds = 0.0;          ///< time the window's samples cover [s] (see ExcitationInformation)
  double since_start_seconds = 0.0;     ///< [s]
  double window_weight = 0.0;           ///< samples in the window (weighted)
  double since_start_weight = 0.0;      ///< samples since start (weighted)
  double threshold = kExcitedVarianceRatio;  ///< the excited_ratio used
  /// Bodies first (RobotDynamics::bodies() order, 10 each: m cx cy cz Ixx Iyy Izz Ixy Iyz Ixz),
  /// then every effect term's values (RobotDynamics::effects() order).
  std::vector<QuantityExcitation> quantities;
};

class ExcitationMonitor {
 public:
  /// @param model the robot whose features Add() is given (copied).
  /// @param measurement_sigma torque noise std per DOF [N m] (model.num_dofs(), each > 0): the
  ///   estimator's measurement_sigma for every channel.
  /// @param prior_covariance P0, the covariance of x before any data (P x P, symmetric positive
  ///   definite, may be dense): RecursiveEstimator::State().P of a fresh estimator, or its diagonal
  ///   (a VectorXd of variances v converts with `Eigen::MatrixXd(v.asDiagonal())`).
  /// @throws std::invalid_argument naming the value: wrong sizes, a sigma not positive and finite,
  ///   P0 not symmetric positive definite, a window not positive and finite, num_blocks < 1, a
  ///   threshold outside (0, 1).
  ExcitationMonitor(const RobotDynamics& model, const Eigen::VectorXd& measurement_sigma,
                    const Eigen::MatrixXd& prior_covariance, const ExcitationOptions& options = {});

  /// Adds one sample's features A (num_dofs x num_features, RobotDynamics::Features, exactly what
  /// OnlineJointEstimator computes) at time t [s], counting weight samples (>= 1 for every k-th
  /// sample given: k; see the file comment). Allocation-free and exception-free; a sample that
  /// cannot be used changes nothing and is reported: kWrongSize (A's shape), kNonFinite (a NaN or
  /// Inf in t or A), kOutOfOrder (t not after the last accepted sample's), kNumerical (weight not
  /// positive and finite). Cost: at most F (F + 1) m / 2 multiply-adds, less where A's columns are
  /// zero on some rows (the 7-DOF arm with friction, F = 84: about 11,000; 3.5 us measured).
  UpdateStatus Add(double t, const Eigen::MatrixXd& A, double weight = 1.0) noexcept;

  /// Forgets every sample (as if just constructed). Allocation-free.
  void Reset() noexcept;

  /// An ExcitationInformation with matrices of this model's size, for CopyInformation().
  ExcitationInformation MakeInformation() const;
  /// Copies the current information into *out (symmetrized). Allocation-free when out's matrices
  /// already have F x F entries (MakeInformation()); resizes them otherwise.
  void CopyInformation(ExcitationInformation* out) const;

  /// Every quantity's excitation at the current parameters x (RobotDynamics parameters, P) from
  /// this monitor's information (see the file comment). Allocates; O(P^3 + F^2 P).
  /// @throws std::invalid_argument if x has the wrong size or is not finite.
  ExcitationReport Evaluate(const Eigen::VectorXd& x) const;
  /// The same from a copy of the information (CopyInformation(), possibly of another monitor of
  /// the same model). @throws std::invalid_argument also if info's matrices are not F x F.
  ExcitationReport Evaluate(const Eigen::VectorXd& x, const ExcitationInformation& info) const;

  /// Gradients of every quantity with respect to x at x, one row each, in the order of
  /// ExcitationReport::quantities (Q x P): body rows J_mci_pi L J_pi_theta (MassComInertiaAboutCom,
  /// ReportFrameMap, the body's log-Cholesky map) in the body's 10 columns; effect rows e^s for
  /// exponential coefficients, 1 for an offset c and a spring's q0. Precondition: x finite with
  /// every body's mass positive (always true of log-Cholesky bodies of a consistent prior).
  Eigen::MatrixXd QuantityGradients(const Eigen::VectorXd& x) const;
  /// The quantities' names and groups, in the same order.
  const std::vector<std::string>& quantity_names() const { return names_; }
  const std::vector<std::string>& quantity_groups() const { return groups_; }

  const RobotDynamics& model() const { return model_; }
  const ExcitationOptions& options() const { return options_; }
  const Eigen::VectorXd& measurement_sigma() const { return sigma_; }
  const Eigen::MatrixXd& prior_covariance() const { return P0_; }
  double block_seconds() const { return block_seconds_; }  ///< window_seconds / num_blocks [s]
  std::uint64_t accepted_samples() const { return accepted_; }  ///< samples Add() accepted (unweighted)
  bool has_time() const { return has_time_; }
  double last_time() const { return last_time_; }  ///< of the last accepted sample [s]

 private:
  void CloseBlocks(std::int64_t up_to_block) noexcept;

  RobotDynamics model_;
  ExcitationOptions options_;
  Eigen::VectorXd sigma_, inverse_sigma_;
  Eigen::MatrixXd P0_, L0_;  ///< P0 = L0 L0^T
  std::vector<std::string> names_, groups_;
  double block_seconds_ = 1.0;

  // Accumulators: lower triangles only.
  Eigen::MatrixXd current_;            ///< the current block
  Eigen::MatrixXd closed_total_;       ///< every closed block
  std::vector<Eigen::MatrixXd> ring_;  ///< the last num_blocks closed blocks (slot = block index % num_blocks)
  std::vector<double> ring_weight_;
  double current_weight_ = 0.0, closed_weight_ = 0.0;
  std::int64_t current_block_ = 0;     ///< index of the current block since first_time_
  std::int64_t closed_blocks_ = 0;     ///< blocks closed since start
  bool has_time_ = false;
  double first_time_ = 0.0, last_time_ = 0.0;
  std::uint64_t accepted_ = 0;

  // Add()'s workspace.
  Eigen::MatrixXd scaled_;               ///< B = sqrt(weight) S^-1 A
  Eigen::MatrixXd transposed_;           ///< rows of B^T for one panel
  Eigen::VectorXi row_first_, row_last_;  ///< per column: first and last non-zero row (first > last: none)
};

/// The names of the quantities not excited in the window (`since_start` false) or since start,
/// in report order, for JSON and LCM.
std::vector<std::string> UnexcitedNames(const ExcitationReport& report, bool since_start);

/// One line in English: "thigh.m and shank.cz are not excited in the last 10 s; since start:
/// shank.cz". One item per body or effect term: a body none of whose quantities is excited is
/// named as a whole ("all of rotor@hip"), else its unexcited quantities follow its name once
/// ("thigh.m/Ixx/Iyy"); beyond `max_items` items the rest is counted ("and 12 more quantities").
/// The window is named by its nominal length, or, while the stream is younger than the window, by
/// the time since start ("in the 3.2 s since start", one scope). Other cases: no samples yet; every
/// quantity excited; the same quantities unexcited in the window and since start ("..., nor since
/// start").
std::string UnexcitedText(const ExcitationReport& report, int max_items = 8);

}  // namespace inertial
