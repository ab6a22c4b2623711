/// @file payload_event.hpp
/// Payload events: a payload picked up or put down, as the online estimator's change detector sees
/// it (kalman_update.hpp: more than max_consecutive_outliers innovations in a row beyond the gate
/// reset the covariance around the current estimate), turned into one value per change: when, on
/// which link, and the added body's mass and centre of mass with their standard deviations.
///
/// When. The estimator leaves x untouched on an outlier. The sample that makes the run longer than
/// max_consecutive_outliers is not an outlier: P is reset and that sample is taken (a
/// Huber-weighted step of up to max_step), so at the detecting sample the estimate has already
/// left the pre-change one (recursive_gauss_newton.cpp, kalman_update.cpp). The detector therefore
/// copies the coefficients w at the first outlier of every run (into memory sized at
/// construction) and keeps that sample's time: the onset, the first sample the changed system made
/// an outlier. The detection time is the sample at which changes_detected() grew.
///
/// What was added: a payload fit against the frozen pre-change model, not the difference of the
/// estimator's link masses. The reset frees every link, and a serial arm's individual link masses
/// are not identifiable from joint torques (they enter only through base parameters, lumped with the
/// first moments of the links before them, and the estimator's covariance is overconfident about
/// them): on the 7-DOF arm, 20 s after a 2 kg payload was put on link7, the estimator's link7 mass
/// had gone 0.506 -> 0.465 kg while link3 gained 0.70 kg and link5 0.59 kg; ranked by mass change
/// over its std, the pick-up was +0.56 +- 0.03 kg on link5 and the put-down -0.31 +- 0.02 kg on
/// link4 (tests/diagnosis/payload_event_test.cpp, TheEstimatorsLinkMassesDoNotLocateThePayload).
/// Instead, from the detecting sample on, with w_b the pre-change coefficients and A(q, qd, qdd)
/// the model's features (RobotDynamics::Features),
///   r_k = tau_k - A_k w_b = A_k,B dpi_B + e_k        (A_k,B: the 10 columns of tree body B)
/// is fitted by least squares for every candidate body B (each tree body: links, rotors; a payload
/// effect shares its link's columns), from the normal equations accumulated per sample:
///   N_B = sum_k A_k,B^T A_k,B,  g_B = sum_k A_k,B^T r_k,  dpi_B = N_B^-1 g_B,
///   RSS_B = sum_k |r_k|^2 - g_B^T dpi_B,   s_B^2 = RSS_B / (num_dofs K - 10),   cov(dpi_B) = s_B^2 N_B^-1.
/// The event's link is the body of least RSS (the one whose added rigid body explains the change);
/// dpi is mapped to that body's report frame (ReportFrameMap), and
///   added mass dm = dpi_m (negative for a put-down), std sqrt(cov_mm);
///   COM of the added body c = dh / dm,  J_c_dpi = [-dh / dm^2, 1 / dm, 0],  cov(c) = J cov(dpi) J^T
/// (first order; a put-down gives the removed body's COM: dh and dm both change sign).
/// Neglected: the pre-change model's own error, except through s_B (it estimates the residual's
/// spread, which includes whatever of that error the fit cannot absorb, but treats it as white); a
/// payload that is not rigidly fixed to one link; the second-order terms of dh / dm (|dm| is many
/// of its std when the event settles). The samples of the outlier run itself are not used (their
/// features were not computed: the ordinary tick stays a counter comparison). The model error is
/// what limits accuracy once the noise is averaged out: on the tests' arm (0.1 N m noise, 1 s of
/// fit) a 2 kg put-down came out at -2.0046 +- 0.0009 kg and its COM 4-5 mm off against a std
/// of 1 mm, from the pre-change (loaded) estimate's error; neither the fit's residual nor the
/// estimator's covariance (0.6 g, propagated) shows it, so a caller should allow ~0.5 % of the
/// mass and ~1 cm of COM beyond the reported std.
///
/// The settle rule (PayloadEventOptions). Every check_interval of sample time from
/// min_settle_time after detection on, the fit is solved; the event is emitted at the first check
/// where std(dm) <= mass_std_fraction |dm| (the mass known to that fraction), or at max_settle_time
/// whatever (settled false). A second change detected while one is settling emits the first at
/// once, with the data it has (settled false). The defaults and why: PayloadEventOptions.
///
/// Cost. Observe() compares four counters per tick; at the first outlier of a run it copies w (F
/// doubles). While a change settles it computes the sample's features and adds to the normal
/// equations of every candidate (for the 7-DOF arm about as much as the estimator's own tick), and
/// solves 10 x 10 systems at each check. None of that allocates; building the emitted event does
/// (the link's name).
///
/// Works with any RecursiveEstimator that reports changes_detected() (recursive Gauss-Newton; the
/// gradient law has no change detector, and linear RLS does not report its count).
/// Conventions: SI units, seconds of sample time (JointSample::t); pi order of types.hpp; the COM
/// c = h / m in the link's report frame (for a URDF link: the link frame).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "inertial/estimation/online/online_joint_estimator.hpp"

namespace inertial {

/// One payload picked up (added_mass > 0) or put down (added_mass < 0) on one link.
struct PayloadEvent {
  double onset_time = 0.0;      ///< [s] the first sample of the outlier run that led to detection
  double detection_time = 0.0;  ///< [s] the sample at which the change detector fired (the covariance reset)
  double settle_time = 0.0;     ///< [s] the sample at which the event was emitted
  bool settled = false;         ///< false: emitted at max_settle_time, or cut short by the next change
  int body = -1;                ///< estimated body (RobotDynamics::bodies() index) the payload is on; -1: unknown
  std::string link;             ///< its name, e.g. "link7"; "(unknown)" when no fit had a solution
                                ///< (the arm did not move enough), with NaN quantities
  double added_mass = 0.0;      ///< [kg] negative for a put-down
  double added_mass_std = 0.0;  ///< [kg]
  Vector3 com = Vector3::Zero();      ///< [m] p_LoPcm_L: the added body's COM in the link's report frame
  Vector3 com_std = Vector3::Zero();  ///< [m] per axis
  Vector10 added_pi = Vector10::Zero();  ///< the added body's pi in the link's report frame (types.hpp order)
  double residual_rms = 0.0;    ///< [N m] s of the fit: RMS torque residual per joint after the payload
  double runner_up_rms = 0.0;   ///< [N m] the same for the next best body (how clearly the link is told apart)
  int runner_up_body = -1;      ///< that body (-1: none)
  std::string runner_up_link;   ///< its name
  int num_samples = 0;          ///< samples in the fit
};

/// One line: "t = 12.34 s: payload picked up on link7: +2.010 +- 0.050 kg at COM (0.000, 0.010,
/// 0.080) +- (0.002, 0.002, 0.004) m (onset 12.22 s, settled at 13.34 s)"; "put down" for a negative
/// added mass, "not settled at" for an event emitted unsettled. t is the detection time.
std::string PayloadEventText(const PayloadEvent& event);

struct PayloadEventOptions {
  /// [s] earliest emission after detection. 1 s: the fit must tell the last links apart, which the
  /// data do only once the arm has moved through a good part of its workspace (on the tests' arm
  /// and excitation the runner-up's residual separates within a few tenths of a second; 1 s keeps a
  /// margin for slower motions), and a mass std of a few percent is reached within that time for
  /// any payload the change detector can see (those are tens of measurement sigmas of torque).
  double min_settle_time = 1.0;
  /// std(added mass) <= this fraction of |added mass|. 0.02: the mass to 2 % (a 50-sigma change).
  double mass_std_fraction = 0.02;
  /// [s] emitted whatever after this long (settled false). 10 s: ten times min_settle_time; a fit
  /// that does not reach its fraction by then lacks excitation (an arm standing still determines
  /// only part of a body) and is reported as it is.
  double max_settle_time = 10.0;
  /// [s] the fit is solved at most this often (7 or so 10 x 10 solves). 0.1 s: the emission is late by
  /// at most that.
  double check_interval = 0.1;
};

/// Watches an OnlineJointEstimator and emits a PayloadEvent per change its detector takes (file
/// comment). Called by the estimator's thread after every Update().
class PayloadEventDetector {
 public:
  /// Sizes every buffer for `estimator`'s model (the same estimator must be passed to Observe()).
  /// @throws std::invalid_argument naming the option for options out of range (non-finite or
  /// negative times, check_interval <= 0, min_settle_time > max_settle_time, mass_std_fraction
  /// outside (0, 1]).
  PayloadEventDetector(const OnlineJointEstimator& estimator, const PayloadEventOptions& options = {});

  /// After each estimator.Update(sample), with that sample. Returns the event when one is emitted
  /// (at most one per call). Allocates only when it returns an event; never throws.
  /// Precondition: called after every Update (a skipped call may miss the start of an outlier run:
  /// its onset and pre-change coefficients are then taken at the next call).
  std::optional<PayloadEvent> Observe(const OnlineJointEstimator& estimator, const JointSample& sample);

  /// A change is detected and its event not yet emitted.
  bool settling() const { return pending_; }
  /// Changes seen (events emitted or pending).
  std::uint64_t changes_seen() const { return changes_seen_; }
  const PayloadEventOptions& options() const { return options_; }

 private:
  struct Candidate {
    int tree_body = -1;  // its 10 columns of A start at 10 tree_body
    int body = -1;       // the estimated body reported (the first on that tree body)
    Matrix10 N = Matrix10::Zero();
    Vector10 g = Vector10::Zero();
  };
  // Adds the sample to every candidate's normal equations.
  void Accumulate(const OnlineJointEstimator& estimator, const JointSample& sample);
  // Solves every candidate's fit; the event of the best (settled per the rule), or false if no
  // candidate's N is positive definite.
  bool Solve(const OnlineJointEstimator& estimator, double t, PayloadEvent* event) const;
  // The pending change's event (no longer pending): settled as the rule says, false if cut short;
  // without a solvable fit, body -1, link "(unknown)" and NaN quantities.
  PayloadEvent Finish(const OnlineJointEstimator& estimator, double t, bool cut_short);

  PayloadEventOptions options_;
  std::uint64_t last_outliers_ = 0, last_accepted_ = 0, last_numerical_ = 0, last_changes_ = 0, changes_seen_ = 0;
  bool in_run_ = false;       // the last observed samples were outliers
  double run_onset_ = 0.0;    // time of this run's first outlier
  Eigen::VectorXd w_run_;     // w at this run's first outlier
  // The change being settled.
  bool pending_ = false;
  double onset_ = 0.0, detection_ = 0.0, next_check_ = 0.0;
  Eigen::VectorXd w_before_, residual_;
  Eigen::MatrixXd A_;
  TreeWorkspace workspace_;
  std::vector<Candidate> candidates_;
  double rss_total_ = 0.0;  // sum of |r_k|^2
  int num_samples_ = 0;
};

}  // namespace inertial
