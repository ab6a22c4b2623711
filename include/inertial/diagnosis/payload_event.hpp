/// @file payload_event.hpp
/// Payload events: a payload picked up or put down, found from the prediction errors of a
/// reference model by a sequential two-sample generalized likelihood ratio (GLR) test, confirmed on
/// samples the test has not seen, located on a link, and reported as one value per change: when,
/// on which link, and the added body's mass and centre of mass with their standard deviations.
///
/// The model of a change. With A(q, qd, qdd) the model's features (RobotDynamics::Features) and
/// w_ref the reference coefficients (below), the prediction error of sample k is
/// r_k = tau_k - A_k w_ref. A rigid body dpi added to tree body B (a payload on link B) changes it
/// by A_k,B dpi (A_k,B: B's 10 columns). The part of w_ref's own error that a body on B explains is
/// there before and after a change alike; so the test is a two-sample one (Chow's): over a
/// reference span R before a candidate onset and the window W from the onset to now, with each
/// joint's error divided by its noise scale s_j (S = diag(s)),
///   N_X = sum_{k in X} A_k,B^T S^-2 A_k,B,   g_X = sum_{k in X} A_k,B^T S^-2 r_k,   X = R, W,
///   LR_B(onset) = g_R^T N_R^-1 g_R + g_W^T N_W^-1 g_W - g_P^T N_P^-1 g_P    (P = R + W pooled):
/// the drop of the squared normalized error when R and W each get a body of their own on B instead
/// of one body for both. For white errors of scale s_j it is chi-square with (at most) 10 degrees of
/// freedom when nothing changed on B. Sums are kept per block of block_time (one 10 x 10 N and one
/// g per candidate link); R is up to reference_time, onsets the block starts of the last max_window.
/// Directions of N weaker than 1e-6 of its mean eigenvalue are left out of every solve (a ridge).
///
/// Noise and its correlation, from the data. s_j is the median block RMS of joint j's error
/// (measured at arming over calibration_time). Real errors
/// are not white (filtered signals, model error that varies along the trajectory): LR is then
/// larger. Its inflation phi_B is estimated on the reference span by the block sandwich: with
/// d = N_R^-1 g_R and groups G of consecutive blocks (0.5 s and 1 s), u_G = g_G - N_G d has
/// E[sum_G u_G^T M u_G] = phi sum_G (tr(M N_G) - tr((M N_G)^2)) (M = N_R^-1) when each group's error
/// has covariance phi N_G; the larger estimate of the two group lengths is taken (floored at 0.5).
/// The decision:
///   LR_B(onset) / phi_B > c,   P(chi2_10 > c) = false_alarm_rate / (tests per hour),
/// a Bonferroni bound over every onset and link tested per block (tests per hour = 3600 /
/// block_time x onsets x links), chi2_10's tail in closed form (even degrees of freedom).
///
/// Confirmation on new samples. A GLR fits its window; a model error that varies along the
/// trajectory can look like a body over one stretch. The change found, delta = dpi_W - dpi_R, must
/// then predict the samples that come after it, which the test did not use: over those blocks
/// (N_n, g_n), gain = 2 (g_n - N_n dpi_R)^T delta - delta^T N_n delta (the drop of the squared
/// error), expected = delta^T N_n delta, its noise std 2 sqrt(phi expected). Confirmed when gain >=
/// expected / 2 and gain >= 3 stds; refuted when the new data are informative (expected / 2 >= 3
/// stds) and gain < expected / 2; dropped unconfirmed after confirm_time. Onsets before a refuted
/// firing are not tested again.
///
/// The event. From confirmation on, at every block, the link and the onset (within 5 blocks of the
/// test's) are chosen together by likelihood: the largest g_W^T N_W^-1 g_W + g_R^T N_R^-1 g_R over
/// the same blocks (LR's pooled term differs between links). The change is then fitted without
/// the onset block and the one before it (they hold samples of both systems), dpi = dpi_W - dpi_R,
/// covariance phi (N_W^-1 + N_R^-1), mapped to the link's report frame (ReportFrameMap); added mass
/// dm = dpi_m, COM c = dh / dm, cov(c) = J cov(dpi) J^T with J_c_dpi = [-dh / dm^2, 1 / dm, 0]
/// (first order). Emitted at least min_settle_time after the onset once settled: std(dm) <=
/// mass_std_fraction |dm| and |c| within reach (the robot's longest segment: LongestSegment, the
/// bound RobotDynamics puts on a payload effect's region); or, not settled by max_settle_time, as a
/// clear mass change (|dm| >= 10 std, within reach); else no event (a drift of the reference, a
/// change of friction or of a sensor). A change whose mass is within 3 stds of zero at
/// min_settle_time is dropped then (it would hold the detector for max_settle_time). While a change
/// is confirmed or settled the tests go on for later onsets, and a stronger one supersedes it. A gap
/// in the stream and Flush() (the end of a stream) conclude a settling change on the data so far.
/// After an event w_ref takes the change (the link's 10 coefficients += delta); the link's own
/// gradients since the change are corrected exactly (g_b -= N_b delta), so its reference runs from
/// the change on and a put-down after a pick-up is found the same way, as a negative body, once
/// min_reference_time has passed since the pick-up; the other links' references start at the event
/// (their gradients would need cross terms with the link's columns, which are not kept).
///
/// The reference model. The detector arms arm_time after the first sample (the online fit: and
/// once it has solved) and takes the estimate as w_ref. It then keeps a shadow: the estimate at the
/// shadow's start, w_next, collects its own g beside w_ref's (N does not depend on the model); after
/// min_reference_time it replaces w_ref if it predicted those blocks better (out of sample), and a
/// new shadow starts; s_j stay those of arming (one weighting within a reference: phi scales the
/// statistic to the errors as they are). So the reference follows the estimate while it learns, without a blind span,
/// and after an event keeps the change until the estimate (whose statistics mix the samples with
/// and without the payload) predicts better. A gap in the stream longer than max_window re-arms.
/// Measured: in the first 10 s of clean simulated streams the test fires now and then (ratios up to
/// 1.5) where the trajectory goes where the estimate had not been; the samples after refute it.
///
/// Cost. Per sample: the features (the estimator's own when the sample's qdd was measured), the
/// errors against w_ref and w_next, and one weighted rank-m update of a 10 x 10 matrix per link; per
/// block: the tests, three 10 x 10 Cholesky solves per onset and link, and the sandwich. On the
/// 3-DOF leg's replay, 11 % of the throughput. Nothing allocates after construction except building
/// the emitted event (the link's name).
///
/// Works with every estimator kind. Conventions: SI units, seconds of sample time (JointSample::t);
/// pi order of types.hpp; the COM c = h / m in the link's report frame (for a URDF link: the link frame).
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
  double onset_time = 0.0;      ///< [s] the start of the block the change began in (the GLR's onset)
  double detection_time = 0.0;  ///< [s] the sample at which the test fired
  double settle_time = 0.0;     ///< [s] the sample at which the event was emitted (confirmed)
  bool settled = false;         ///< false: emitted at max_settle_time before its mass was known to mass_std_fraction
  int body = -1;                ///< estimated body (RobotDynamics::bodies() index) the payload is on
  std::string link;             ///< its name, e.g. "link7"
  double added_mass = 0.0;      ///< [kg] negative for a put-down
  double added_mass_std = 0.0;  ///< [kg]
  Vector3 com = Vector3::Zero();      ///< [m] p_LoPcm_L: the added body's COM in the link's report frame
  Vector3 com_std = Vector3::Zero();  ///< [m] per axis
  Vector10 added_pi = Vector10::Zero();  ///< the added body's pi in the link's report frame (types.hpp order)
  double statistic = 0.0;       ///< LR / phi of the link's change at emission (onset to emission)
  double threshold = 0.0;       ///< the test's c
  double kappa = 1.0;           ///< phi: the inflation the statistic was divided by (file comment)
  /// How much better the link explains the change than the next best one: the difference of their
  /// drops of the squared normalized error, over phi (a chi-square-like margin: tens or more is clear)
  double runner_up_margin = 0.0;
  int runner_up_body = -1;      ///< that body (-1: none)
  std::string runner_up_link;   ///< its name
  int num_samples = 0;          ///< samples from the onset to the emission
};

/// One line: "t = 12.34 s: payload picked up on link7: +2.010 +- 0.050 kg at COM (0.000, 0.010,
/// 0.080) +- (0.002, 0.002, 0.004) m (onset 12.20 s, settled at 13.34 s)"; "put down" for a negative
/// added mass, "not settled at" for an event emitted unsettled. t is the detection time.
std::string PayloadEventText(const PayloadEvent& event);

struct PayloadEventOptions {
  /// [s] the test's time step: onsets are block starts, and the tests run at every block's end.
  /// 0.1 s: a pick-up is placed to 0.1 s, and the per-block work (tests) stays a small part of the
  /// per-sample work at any rate from 100 Hz up.
  double block_time = 0.1;
  /// [s] onsets are searched this far back. 2 s: a change must be found within 2 s.
  double max_window = 2.0;
  /// [s] the reference span before an onset: the longest. 10 s: five windows, enough for the
  /// pre-existing error on every body to be fitted well, short enough to follow a slow drift.
  double reference_time = 10.0;
  /// [s] ... and the shortest before any test: 3 s (30 blocks: 6 groups of five, 3 of ten for phi).
  double min_reference_time = 3.0;
  /// [s] the noise scales are measured over this much after arming. 1 s: 10 block RMS values a
  /// joint, whose median is within ~20 % of the scale (the test is insensitive to that: phi
  /// scales with it).
  double calibration_time = 1.0;
  /// [s] the detector arms this long after the first sample (the online fit: and once it has
  /// solved). 2 s: the estimate of 2 s of excitation predicts well enough that its error does not
  /// dominate s_j; the detector is blind for arm + calibration + reference time (6 s) at the start.
  double arm_time = 2.0;
  /// Expected false events per hour of stream at white noise. 1e-3: one per 1000 hours, the
  /// Bonferroni bound over every test; confirmation lowers it further.
  double false_alarm_rate = 1e-3;
  /// [s] a change not confirmed within this long after the test fired is dropped.
  double confirm_time = 1.0;
  /// std(added mass) <= this fraction of |added mass| to emit. 0.03: a 10 % error is then more
  /// than three stds.
  double mass_std_fraction = 0.03;
  /// [s] the event is emitted no earlier than this after its onset: 1 s, half the 2 s it must be
  /// found within; the fit then covers 1 s of motion (a COM to millimetres on the tests' arm where
  /// 0.2 s gave centimetres) where confirmation alone may come 0.1 s after the onset.
  double min_settle_time = 1.0;
  /// [s] after confirmation, emitted whatever after this long (settled false).
  double max_settle_time = 5.0;
};

/// Watches an OnlineJointEstimator's stream and emits a PayloadEvent per confirmed change (file
/// comment). Called by the estimator's thread after every Update() of a sample the pipeline passed.
class PayloadEventDetector {
 public:
  /// Sizes every buffer for `estimator`'s model (the same estimator must be passed to Observe()).
  /// @throws std::invalid_argument naming the option for options out of range (non-finite or
  /// non-positive times, reference or window shorter than a block, false_alarm_rate outside
  /// (0, 1e6], mass_std_fraction outside (0, 1]).
  PayloadEventDetector(const OnlineJointEstimator& estimator, const PayloadEventOptions& options = {});

  /// After each estimator.Update(sample), with that sample (outliers of the estimator included: a
  /// payload's samples may be refused by its gate). Returns the event when one is emitted (at most
  /// one per call). Allocates only when it returns an event; never throws. A sample of the wrong
  /// size or with a non-finite value is ignored.
  std::optional<PayloadEvent> Observe(const OnlineJointEstimator& estimator, const JointSample& sample);
  /// At the end of a stream: a confirmed change still settling is concluded on the data so far (an
  /// event if its mass is known to mass_std_fraction, or is a 10-sigma change within reach). Also
  /// done by Observe() at a gap longer than max_window. Allocates only when it returns an event.
  std::optional<PayloadEvent> Flush(const OnlineJointEstimator& estimator);

  /// A change is being confirmed or settled.
  bool settling() const { return phase_ == Phase::kConfirming || phase_ == Phase::kSettling; }
  /// The tests run (armed, calibrated, enough reference).
  bool testing() const;
  /// Changes the test fired on (confirmed or not) and those confirmed.
  std::uint64_t changes_seen() const { return fired_; }
  std::uint64_t changes_confirmed() const { return confirmed_; }
  /// The largest LR / phi over threshold seen at any test so far (how near the stream came).
  double largest_ratio() const { return largest_ratio_; }
  /// The noise scales s_j (zero before calibration) and the best link's inflation phi at the last test.
  const Eigen::VectorXd& noise() const { return sigma_; }
  double kappa() const { return kappa_; }
  double threshold() const { return threshold_; }
  const PayloadEventOptions& options() const { return options_; }

 private:
  enum class Phase { kWaiting, kCalibrating, kArmed, kConfirming, kSettling };
  struct Block {
    double t0 = 0.0;
    int n = 0;
    Eigen::VectorXd sum_rr, sum_rr_next, sum_tt;  // per joint: r^2 against w_ref and w_next, tau^2
    std::vector<Matrix10> N;         // per candidate: sum A_B^T S^-2 A_B (independent of w_ref)
    std::vector<Vector10> g, g_next; // per candidate: sum A_B^T S^-2 r against w_ref, and against w_next
  };
  struct Fit {  // a change: window less reference on one candidate
    int candidate = -1;
    // Block indices (absolute): the onset, the test's (Refit searches near it), the fit's window
    // start (after the blocks around the onset), the reference's earliest.
    std::int64_t onset = 0, test_onset = 0, window_lo = 0, regime = 0;
    double ratio = -1.0, statistic = 0.0, runner_up = 0.0, kappa = 1.0;
    int runner_up_candidate = -1;
    Vector10 delta = Vector10::Zero(), d_ref = Vector10::Zero();
    Matrix10 cov = Matrix10::Zero();
  };

  void Arm(const OnlineJointEstimator& estimator, double t);
  void StartBlock(double t0);
  void EndBlock(const OnlineJointEstimator& estimator, double t, std::optional<PayloadEvent>* emitted);
  void Calibrate();
  void Test(double t);
  void Confirm(double t);
  // force: conclude now (the stream ended or broke off) as at max_settle_time.
  void Settle(const OnlineJointEstimator& estimator, double t, std::optional<PayloadEvent>* emitted, bool force);
  std::int64_t Regime(int c) const;  // the first block candidate c's references may use
  bool Supersede(double t);  // a later, stronger change replaces the pending one (file comment)
  static constexpr int kOnsetSearch = 5;  // Refit's onsets: within this many blocks of the test's
  void Rebase(const OnlineJointEstimator& estimator);
  Block& BlockAt(std::int64_t index) { return ring_[static_cast<size_t>(index % static_cast<std::int64_t>(ring_.size()))]; }
  const Block& BlockAt(std::int64_t index) const {
    return ring_[static_cast<size_t>(index % static_cast<std::int64_t>(ring_.size()))];
  }
  // Sums of blocks [from, to) of candidate c.
  void Sum(int c, std::int64_t from, std::int64_t to, Matrix10* N, Vector10* g) const;
  // The block sandwich's inflation of candidate c's statistic over reference blocks [from, to).
  double Inflation(int c, std::int64_t from, std::int64_t to) const;
  // The best change over every candidate and its onsets up to last_onset; false if none tested.
  bool BestChange(std::int64_t last_onset, Fit* best) const;
  // The change re-fitted on blocks [onset, end) on every candidate, the best kept.
  void Refit(Fit* fit, std::int64_t end) const;
  PayloadEvent MakeEvent(const OnlineJointEstimator& estimator, const Fit& fit, double t, bool settled) const;

  PayloadEventOptions options_;
  int m_ = 0;
  std::vector<int> candidates_block_, candidates_body_;  // per candidate: column block, reported body
  std::vector<Block> ring_;
  std::int64_t block_ = -1;           // index of the open block (absolute); ring_ holds the last ring_.size()
  std::int64_t end_ = 0;              // blocks [.., end_) are closed
  std::int64_t regime_ = 0;           // first block of the current reference model and system
  std::int64_t no_onset_before_ = 0;  // onsets before it were examined (a refuted change) or are another system
  std::int64_t calibration_start_ = 0, shadow_start_ = -1;
  std::vector<std::int64_t> candidate_regime_;  // per candidate: the first block after an event (see Settle)
  int window_blocks_ = 0, reference_blocks_ = 0, min_reference_blocks_ = 0, calibration_blocks_ = 0;
  int onsets_ = 0;
  Phase phase_ = Phase::kWaiting;
  double first_t_ = 0.0, last_t_ = 0.0;
  bool seen_ = false;
  double threshold_ = 0.0, kappa_ = 1.0, largest_ratio_ = 0.0;
  double reach_ = 0.0;  // [m] the robot's longest segment (body_region.hpp)
  Eigen::VectorXd w_ref_, w_next_, sigma_, inv_var_, r_, r_next_;
  Eigen::MatrixXd A_;
  TreeWorkspace workspace_;
  // The change being confirmed / settled.
  Fit pending_;
  std::int64_t fired_block_ = 0;
  double fired_t_ = 0.0, confirmed_t_ = 0.0;
  std::uint64_t fired_ = 0, confirmed_ = 0;
  mutable std::vector<double> scratch_;  // block RMS values, candidates' likelihoods (sized at construction)
  // s_j: the median block RMS of joint j's error over blocks [from, to).
  void SetNoise(std::int64_t from, std::int64_t to);
};

/// P(chi2_k > x) for even k (closed form: e^{-x/2} sum_{i < k/2} (x/2)^i / i!).
double ChiSquareTailEven(int k, double x);
/// The c with ChiSquareTailEven(k, c) = p (bisection; 0 < p < 1).
double ChiSquareQuantileEven(int k, double p);

}  // namespace inertial
