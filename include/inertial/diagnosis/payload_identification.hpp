/// @file payload_identification.hpp
/// A payload held by a robot, identified from joint logs so that a controller can load it: its
/// mass, centre of mass and rotational inertia about its centre of mass in the frame of the link
/// that holds it, with standard deviations and the quantities the prior rather than the data
/// determines ("held by the prior", fit_uncertainty.hpp). Two ways, both the batch fit of
/// joint_identification.hpp (eq. 14) on a model with a `payload@LINK` body, every link held at its
/// prior (JointIdentificationOptions::frozen_bodies):
///
/// - Against the model (IdentifyPayload): the run with the payload fitted by the model (the URDF's
///   links, frozen, plus the model's effects, fitted) and the payload body. What the URDF gets wrong
///   about the links goes into the payload (or the effects).
/// - From the difference (IdentifyPayloadFromDifference): the same trajectory recorded without
///   the payload (the baseline) is subtracted sample by sample, so that whatever the two runs share
///   (friction, the links' errors, sensor offsets) cancels. The with-payload sample k, of state
///   x_k = (q_k, qd_k, qdd_k), is paired with the baseline's sample b_k (below) and
///     dtau_k = tau_with,k - tau_base(b_k) - [A(x_k) - A(x_b,k)] w_links
///            = Y_P(x_k) pi_P + [A(x_k) - A(x_b,k)] (w_true - w_links) + (friction, noise),
///   with A the links' regressor, w_links the frozen links' coefficients (the model's prior torque
///   without the payload), w_true the real links' and Y_P the payload's regressor (its link's 10
///   columns of A) at the with-run's state. The bracket is the baseline's torque transported to
///   the with-run's state by the model: what the links' torque changes between the two states,
///   as the URDF predicts it. Without it, dtau held the whole [A(x_k) - A(x_b,k)] w_true, first
///   order in the state mismatch; with it only (the model's error) x (the mismatch) remains, a
///   second-order term. The existing fit does exactly this least-squares problem if it is given a
///   model whose links are all frozen at their priors, whose only free body is the payload and
///   which has no effects, on data whose torque is dtau + A(x_k) w_links = tau_with,k - tau_base(b_k)
///   + A(x_b,k) w_links: its residual is
///     A w(x) - (dtau + A w_links) = A (w_links + pi_P(theta)) - dtau - A w_links = Y_P pi_P - dtau,
///   so the data term is ||Y_P pi_P - dtau||^2 and only the payload's log-det prior adds to it.
///   Friction is not transported (the model has none): a velocity mismatch dqd leaves F_v dqd of
///   viscous friction in dtau, which the time shift below makes small and the residual shows.
///
///   Pairing. A robot repeating a trajectory under another load tracks it a little differently,
///   and a recording is rarely started at the same instant of the motion. The baseline is read at
///   the with-sample's time since its run's start plus a constant shift dt (interpolated linearly:
///   q, qd, qdd and tau), dt the one minimizing the positions' mismatch
///     c(dt) = mean_k sum_j ((q_with,j(s_k) - q_base,j(s_k + dt)) / range_j)^2
///   (range_j the joint's range of motion in the with-run, floored at 0.01 rad or m, so that rad and
///   m mix) over the with-samples whose s_k + dt lies in the baseline: first on a grid of the
///   baseline's median step over |dt| <= half the shorter run's duration (so that at least half of
///   it pairs up; a periodic excitation's other periods are as good a match and farther), on at
///   most kGridSamples evenly spread with-samples, then by golden-section search on all of them
///   within one step of the grid's best. Ties go to the smaller |dt|. With-samples whose shifted
///   time falls outside the baseline are left out. What the shift cannot remove (a different
///   tracking error, a scaled path) is the model's to transport.
///
///   Refusal: where the remaining mismatch is too large for the difference, i.e. where the
///   second-order term could be comparable to the payload's torque. The data give its size: the
///   transported torque D_k = [A(x_k) - A(x_b,k)] w_links is what the URDF says the mismatch does
///   to the links' torque, and the term left is D's error. A URDF's link torques are typically
///   10-30 % off (masses and COMs as CAD gives them, without cables, motor housings, paint), but a
///   torque's change with the state can be off by far more: a link whose URDF COM lies near its
///   joint's axis has a small torque and a gradient the URDF gets wrong in whole. Measured on the
///   tests' arm (links whose torque is 11-28 % off the URDF's, a with-run tracking 6-17 % of the
///   range away), the term left was 0.84-1.19 times D. So the refusal takes it to be up to
///   kTransportError = 100 % of D: the transport removes most of it in the common case (a scaled
///   path: 3.3 % of mass error to 0.04 %), but the bound cannot count on that. A least-squares fit
///   moves its fitted torque Y_P pi_P by at most the RMS of a disturbance (the projection onto the
///   payload's columns does not enlarge it), so the payload's fitted torque is off by at most
///   RMS(D), against its own RMS(dtau). The ratio mismatch_torque = RMS(D) / RMS(dtau) (over the
///   pairs and joints: the fit's own norm, where every joint's torque weighs the same; dtau holds
///   the noise of both runs too, which matters only for a payload whose torque is near the noise)
///   is refused above max_mismatch_torque = 0.1, where that worst case reaches 10 % of the
///   payload's torque: beyond it the difference could give an answer tens of per cent off that
///   neither its std nor its residual would show. The worst case is pessimistic (a mismatch torque
///   is mostly not a payload's: the projection keeps little of it), so an accepted pairing is
///   usually far better (docs/payload.md has the tests' figures). The threshold is reasoned, not
///   tuned; on the tests' data it leaves room on both sides: a baseline of another trajectory puts
///   the links' whole gravity torque in D (ratio 8.9), the repeat of one trajectory 0.3-1 % of the
///   range apart 0.003-0.03. A small payload makes the same mismatch matter more (its torque is
///   smaller), which is right: the refusal says so, and a larger max_mismatch_torque (the CLI's
///   --max-mismatch-torque) accepts it at the stated cost. Reported: the shift (time_shift), the
///   positions' mismatch before and after it (position_mismatch_unshifted, position_mismatch: the
///   largest joint's RMS q mismatch / its range) and mismatch_torque.
///
/// Standard deviations: the fit's, with the data's part the larger of the white-noise one and the
/// block sandwich's over the residual's time blocks (fit_uncertainty.hpp), so that a residual
/// correlated in time or carrying model error widens them.
///
/// Model error. Against the model, what the URDF and the effects get wrong about the links goes
/// into the payload and no std can say by how much. The residual shows whether there is such an
/// error: measurement noise changes from sample to sample, a model's error follows the motion and
/// changes smoothly. With r the residual (every joint and sample), the sample-to-sample estimate
/// of the white part's variance is s_d^2 = mean((r_{i+1} - r_i)^2) / 2 (exact for white noise, and
/// blind to a smooth component, whose differences are small; von Neumann, Ann. Math. Stat. 1941),
/// and residual_rms^2 / s_d^2 = 1 / (1 - rho_1) (rho_1 the lag-1 autocorrelation). model_error is
/// set where residual_rms > sqrt(2) s_d, i.e. where the smooth part's variance (residual_rms^2 -
/// s_d^2) exceeds the white part's, rho_1 > 0.5: more of the residual is model than noise. For a
/// white residual the ratio is 1 with a standard error of about 1/sqrt(2 N_rows), so sqrt(2) is no
/// chance value on any log worth fitting. Torques low-passed before they were logged make the noise
/// itself smooth and trip it as well; either way the std cannot vouch for the payload, and a
/// baseline (the same trajectory without the payload, IdentifyPayloadFromDifference) cancels both.
///
/// Conventions: SI units (kg, m, kg m^2); the payload in its link's frame (the URDF link frame of
/// LINK, also for a link merged by a fixed joint, e.g. tool0); inertia about the COM with the
/// tensor's entries (Ixy the (0,1) entry, as URDF's ixy), pi order of types.hpp.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "inertial/estimation/batch/joint_identification.hpp"
#include "inertial/estimation/fit_uncertainty.hpp"
#include "inertial/model/region_plausibility.hpp"

namespace inertial {

struct PayloadIdentificationOptions {
  /// The fit's settings (prior weight, Levenberg-Marquardt); frozen_bodies and initial are set here
  /// (every body but the payload frozen; the default start).
  JointIdentificationOptions fit;
  /// Difference only: the largest RMS torque the remaining state mismatch predicts for the links,
  /// as a fraction of the RMS of the (transported) difference (file comment: at 0.1, the model's
  /// error in that torque could be 10 % of the payload's).
  double max_mismatch_torque = 0.1;
};

/// How the baseline was paired with the run with the payload (file comment).
struct BaselinePairing {
  /// [s] the with-sample at time s since its run's start pairs with the baseline at s + time_shift
  /// since the baseline's start (negative: the baseline's recording started late in the motion).
  double time_shift = 0.0;
  double position_mismatch_unshifted = 0.0;  ///< the largest joint's RMS q mismatch / its range at dt = 0
  std::string unshifted_joint;               ///< that joint
  double position_mismatch = 0.0;            ///< the same for the pairs fitted (after the shift)
  std::string mismatch_joint;                ///< that joint
  double mismatch_torque_rms = 0.0;          ///< [N m] RMS of D = [A(x_with) - A(x_base)] w_links
  double difference_rms = 0.0;               ///< [N m] RMS of dtau (transported)
  double mismatch_torque = 0.0;              ///< their ratio, refused above max_mismatch_torque
  int num_pairs = 0;                         ///< pairs fitted
};

/// The identified payload (file comment).
struct PayloadIdentification {
  std::string link;               ///< the link that holds it
  int body = -1;                  ///< its index in model.bodies() ("payload@<link>")
  InertialParams payload;         ///< in the link's frame
  BodyUncertainty uncertainty;    ///< standard deviations (inertia entries Ixx Iyy Izz Ixy Iyz Ixz)
  BodyHeldByPrior held;           ///< which quantities the prior, not the data, determines
  bool from_difference = false;   ///< fitted to the difference with a baseline run
  BaselinePairing pairing;        ///< difference: how the baseline was paired (file comment)
  int num_samples = 0;            ///< samples fitted (pairs, for the difference)
  double residual_rms = 0.0;      ///< [N m] RMS torque residual per joint and sample after the fit
  double noise_sigma = 0.0;       ///< [N m] the noise the uncertainty estimated from the residual
  double residual_white_noise = 0.0;  ///< [N m] s_d: the residual's sample-to-sample (white) part (file comment)
  bool model_error = false;       ///< residual_rms > sqrt(2) s_d: the residual is mostly smooth (file comment)
  int time_blocks = 0;            ///< the uncertainty's time blocks (fit_uncertainty.hpp)
  int block_length = 0;           ///< their length [samples]
  double correlation_time = 0.0;  ///< the residual's integrated autocorrelation time [samples]
  /// The payload against its region (a ball of the robot's longest segment about its link,
  /// body_region.hpp; region_plausibility.hpp), nullopt if it has none; `region` names its source.
  std::optional<RegionPlausibility> plausibility;
  std::string region;
  JointIdentificationResult fit;  ///< the whole fit (x of `model`)
};

/// The index in model.bodies() of the body "payload@<link>".
/// @throws std::invalid_argument if the model has none (naming the link).
int PayloadBody(const RobotDynamics& model, const std::string& link);

/// The run with the payload against the model: every body but payload@<link> frozen at its
/// prior, the model's effects and the payload fitted.
/// @throws std::invalid_argument if the model has no payload@<link>, the samples do not match the
/// model, or there are too few samples for an uncertainty.
PayloadIdentification IdentifyPayload(const RobotDynamics& model, const std::string& link,
                                      const JointSamples& with_payload,
                                      const PayloadIdentificationOptions& options = {});

/// The difference data of the file comment: the with-payload samples that have a baseline sample
/// at their time since start plus the shift, with tau = tau_with - tau_base + A(x_base) w_links
/// (the baseline interpolated). *pairing (optional) gets how they were paired, also when refused.
/// @throws std::invalid_argument if the model has effects or no payload@<link>, the logs' joints
/// differ from the model's, a log has fewer than two samples or a time that does not increase,
/// fewer than two samples pair up, or mismatch_torque exceeds max_mismatch_torque (the message
/// gives the shift, the ratio and its tolerance, and the joint whose positions differ most).
JointSamples PayloadDifferenceSamples(const RobotDynamics& model, const std::string& link,
                                      const JointSamples& with_payload, const JointSamples& baseline,
                                      double max_mismatch_torque, BaselinePairing* pairing = nullptr);

/// The payload from the difference with a baseline run of the same trajectory (file comment).
/// `model`: the links and payload@<link>, no effects.
/// @throws as PayloadDifferenceSamples and IdentifyPayload.
PayloadIdentification IdentifyPayloadFromDifference(const RobotDynamics& model, const std::string& link,
                                                    const JointSamples& with_payload, const JointSamples& baseline,
                                                    const PayloadIdentificationOptions& options = {});

}  // namespace inertial
