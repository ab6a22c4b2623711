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
///   (friction, the links' errors, sensor offsets) cancels. Pairing: each with-payload sample at
///   time s since its run's start takes the baseline's torque at the same s, interpolated linearly
///   (with-payload samples beyond the baseline's end are left out). Then
///     dtau_k = tau_with,k - tau_baseline(s_k) = Y_P(q_k, qd_k, qdd_k) pi_P + (noise, mismatch),
///   with Y_P the payload's regressor (its link's 10 columns of A) at the with-run's state. The
///   existing fit does exactly this least-squares problem if it is given a model whose links are
///   all frozen at their priors, whose only free body is the payload and which has no effects, on
///   data whose torque is dtau + A w_links, where w_links are the frozen links' coefficients (the
///   model's prior torque without the payload): its residual is
///     A w(x) - (dtau + A w_links) = A (w_links + pi_P(theta)) - dtau - A w_links = Y_P pi_P - dtau,
///   so the data term is ||Y_P pi_P - dtau||^2 and only the payload's log-det prior adds to it.
///   The pairing assumes the two runs follow the same path at the same times: a position mismatch
///   dq adds about (d tau_links / d q) dq of the links' torque to dtau, which the fit attributes to
///   the payload. It is refused (std::invalid_argument naming the joint) when, for some joint, the
///   RMS over the pairs of q_with - q_baseline exceeds max_position_mismatch of that joint's range of
///   motion in the with-run (range floored at 0.01 rad or m). The default, 0.1 %, is measured: on
///   the bundled arm (tests' excitation, 200 Hz, a 1.1 kg and a 2.8 kg payload) a baseline late by
///   5, 10, 20 and 50 ms was off by 0.18-0.20, 0.36-0.39, 0.72-0.79 and 1.8-2.0 % of joint2's
///   range and moved the mass by up to 0.42, 0.92, 2.0 and 6.1 % and the COM by up to 6, 13, 28 and
///   71 mm: the error grows about linearly with the mismatch, and 0.1 % keeps it near 0.2 % of the
///   mass and 3 mm of COM (trajectory_overlap.hpp's 1 % for "the same state" would let 2 % and
///   3 cm through). A baseline of another trajectory is tens of per cent off. A real robot's
///   tracking differs between the runs by what the payload does to its controller; where that is
///   above the default the refusal says so, and a larger --max-mismatch buys the error above.
///   The mismatch measured is reported (position_mismatch).
///
/// Conventions: SI units (kg, m, kg m^2); the payload in its link's frame (the URDF link frame of
/// LINK, also for a link merged by a fixed joint, e.g. tool0); inertia about the COM with the
/// tensor's entries (Ixy the (0,1) entry, as URDF's ixy), pi order of types.hpp.
#pragma once

#include <string>
#include <vector>

#include "inertial/estimation/batch/joint_identification.hpp"
#include "inertial/estimation/fit_uncertainty.hpp"

namespace inertial {

struct PayloadIdentificationOptions {
  /// The fit's settings (prior weight, Levenberg-Marquardt); frozen_bodies and initial are set here
  /// (every body but the payload frozen; the default start).
  JointIdentificationOptions fit;
  /// Difference only: the largest RMS position mismatch between the runs, as a fraction of each
  /// joint's range of motion (file comment, which says what it costs). 0.001.
  double max_position_mismatch = 0.001;
};

/// The identified payload (file comment).
struct PayloadIdentification {
  std::string link;               ///< the link that holds it
  int body = -1;                  ///< its index in model.bodies() ("payload@<link>")
  InertialParams payload;         ///< in the link's frame
  BodyUncertainty uncertainty;    ///< standard deviations (inertia entries Ixx Iyy Izz Ixy Iyz Ixz)
  BodyHeldByPrior held;           ///< which quantities the prior, not the data, determines
  bool from_difference = false;   ///< fitted to the difference with a baseline run
  double position_mismatch = 0.0; ///< difference: the largest joint's RMS q mismatch / its range
  std::string mismatch_joint;     ///< that joint
  int num_samples = 0;            ///< samples fitted (pairs, for the difference)
  double residual_rms = 0.0;      ///< [N m] RMS torque residual per joint and sample after the fit
  double noise_sigma = 0.0;       ///< [N m] the noise the uncertainty estimated from the residual
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
/// at the same time since start, with tau = tau_with - tau_baseline (interpolated) + A w_links.
/// *mismatch (optional) gets the largest joint's RMS q mismatch over its range, *joint that joint.
/// @throws std::invalid_argument if the model has effects or no payload@<link>, the logs' joints
/// differ from the model's, fewer than two samples pair up, or the mismatch exceeds
/// max_position_mismatch (the message names the joint, the mismatch and the tolerance).
JointSamples PayloadDifferenceSamples(const RobotDynamics& model, const std::string& link,
                                      const JointSamples& with_payload, const JointSamples& baseline,
                                      double max_position_mismatch, double* mismatch = nullptr,
                                      std::string* joint = nullptr);

/// The payload from the difference with a baseline run of the same trajectory (file comment).
/// `model`: the links and payload@<link>, no effects.
/// @throws as PayloadDifferenceSamples and IdentifyPayload.
PayloadIdentification IdentifyPayloadFromDifference(const RobotDynamics& model, const std::string& link,
                                                    const JointSamples& with_payload, const JointSamples& baseline,
                                                    const PayloadIdentificationOptions& options = {});

}  // namespace inertial
