#include "inertial/diagnosis/payload_identification.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

#include "inertial/model/number_text.hpp"

namespace inertial {
namespace {

// Every estimated body but the payload frozen at its prior.
std::vector<bool> AllButPayloadFrozen(const RobotDynamics& model, int payload) {
  std::vector<bool> frozen(model.bodies().size(), true);
  frozen[payload] = false;
  return frozen;
}

void CheckJoints(const RobotDynamics& model, const JointSamples& data, const char* which) {
  if (data.joint_names != model.dof_names()) {
    throw std::invalid_argument(std::string("the ") + which + " log's joints differ from the model's");
  }
}

// The model's error in the torque of a state mismatch, relative to that torque, the refusal allows
// for (header: a URDF 10-30 % off in its torques can be wholly wrong in their changes).
constexpr double kTransportError = 1.0;
// With-samples the shift's grid search evaluates (evenly spread); the refinement uses all of them.
constexpr int kGridSamples = 1000;

void CheckTimes(const JointSamples& data, const char* which) {
  for (int i = 0; i < data.size(); ++i) {
    if (!std::isfinite(data.t[i]) || (i > 0 && !(data.t[i] > data.t[i - 1]))) {
      throw std::invalid_argument(std::string("the ") + which + " log's time does not increase at sample " +
                                  std::to_string(i));
    }
  }
}

// The baseline read at a time since its start, linearly interpolated between its samples.
class BaselineReader {
 public:
  struct Point {
    int k = 0;       // interval [k, k + 1]
    double a = 0.0;  // weight of k + 1
  };

  explicit BaselineReader(const JointSamples& baseline)
      : t_(baseline.t),
        q_(baseline.q),
        duration_(baseline.t[baseline.size() - 1] - baseline.t[0]),
        step_(MedianStep(baseline.t)) {}

  double duration() const { return duration_; }
  double step() const { return step_; }

  // The interval and weight at s since the start; false outside [0, duration].
  bool Locate(double s, Point* p) const {
    if (!(s >= 0 && s <= duration_)) return false;
    const double t = t_[0] + s;
    const int last = static_cast<int>(t_.size()) - 2;  // the last interval's start
    // A guess from the median step, then walked to the interval (a uniform log needs no walk).
    int k = std::clamp(static_cast<int>(s / step_), 0, last);
    while (k > 0 && t_[k] > t) --k;
    while (k < last && t_[k + 1] < t) ++k;
    p->k = k;
    p->a = std::clamp((t - t_[k]) / (t_[k + 1] - t_[k]), 0.0, 1.0);
    return true;
  }

  // Row p of `m` (a baseline matrix) at the point.
  static void Interpolate(const Eigen::MatrixXd& m, const Point& p, Eigen::VectorXd* out) {
    *out = ((1 - p.a) * m.row(p.k) + p.a * m.row(p.k + 1)).transpose();
  }

  // The baseline's q at the point.
  void Positions(const Point& p, Eigen::VectorXd* out) const { Interpolate(q_, p, out); }

  // The baseline's q at the point minus `q`, joint j scaled by scale[j], squared and summed.
  double ScaledSquaredDistance(const Point& p, const Eigen::VectorXd& q, const Eigen::VectorXd& scale) const {
    double sum = 0;
    for (int j = 0; j < q.size(); ++j) {
      const double d = ((1 - p.a) * q_(p.k, j) + p.a * q_(p.k + 1, j) - q[j]) * scale[j];
      sum += d * d;
    }
    return sum;
  }

 private:
  static double MedianStep(const Eigen::VectorXd& t) {
    std::vector<double> steps(t.size() - 1);
    for (size_t i = 0; i < steps.size(); ++i) steps[i] = t[i + 1] - t[i];
    std::nth_element(steps.begin(), steps.begin() + steps.size() / 2, steps.end());
    return steps[steps.size() / 2];
  }

  const Eigen::VectorXd& t_;
  const Eigen::MatrixXd& q_;
  double duration_;
  double step_;
};

// c(dt) of the header: the mean over the with-samples i = 0, stride, 2 stride, ... that pair up of
// sum_j ((q_with - q_base) / range_j)^2; infinity if fewer than two pair up.
double ShiftCost(const JointSamples& with, const BaselineReader& reader, const Eigen::VectorXd& inv_range, double dt,
                 int stride) {
  double sum = 0;
  int count = 0;
  BaselineReader::Point p;
  Eigen::VectorXd q(with.q.cols());
  for (int i = 0; i < with.size(); i += stride) {
    if (!reader.Locate(with.t[i] - with.t[0] + dt, &p)) continue;
    q = with.q.row(i).transpose();
    sum += reader.ScaledSquaredDistance(p, q, inv_range);
    ++count;
  }
  return count >= 2 ? sum / count : std::numeric_limits<double>::infinity();
}

// The shift of the header: a grid of the baseline's median step over |dt| <= half the shorter
// run's duration, from 0 outwards (ties to the smaller |dt|), then golden-section search within
// one step of the grid's best.
double BestShift(const JointSamples& with, const BaselineReader& reader, const Eigen::VectorXd& inv_range) {
  const double h = reader.step();
  const double max_shift = 0.5 * std::min(with.t[with.size() - 1] - with.t[0], reader.duration());
  const int stride = std::max(1, with.size() / kGridSamples);
  const int steps = static_cast<int>(std::floor(max_shift / h));
  double best = 0, best_cost = ShiftCost(with, reader, inv_range, 0.0, stride);
  for (int k = 1; k <= steps; ++k) {
    for (const double dt : {k * h, -k * h}) {
      const double cost = ShiftCost(with, reader, inv_range, dt, stride);
      if (cost < best_cost) best = dt, best_cost = cost;
    }
  }
  // Golden section on [best - h, best + h] with every with-sample: c is continuous (linear
  // interpolation) and near its minimum about quadratic; 40 steps shrink the bracket by 0.618^40,
  // 5e-9 of a step.
  const double ratio = (std::sqrt(5.0) - 1) / 2;
  double lo = best - h, hi = best + h;
  double x1 = hi - ratio * (hi - lo), x2 = lo + ratio * (hi - lo);
  double c1 = ShiftCost(with, reader, inv_range, x1, 1), c2 = ShiftCost(with, reader, inv_range, x2, 1);
  for (int it = 0; it < 40; ++it) {
    if (c1 <= c2) {
      hi = x2, x2 = x1, c2 = c1;
      x1 = hi - ratio * (hi - lo);
      c1 = ShiftCost(with, reader, inv_range, x1, 1);
    } else {
      lo = x1, x1 = x2, c1 = c2;
      x2 = lo + ratio * (hi - lo);
      c2 = ShiftCost(with, reader, inv_range, x2, 1);
    }
  }
  const double refined = 0.5 * (lo + hi);
  // The grid's best with every sample: the refinement keeps it unless it found better.
  return ShiftCost(with, reader, inv_range, refined, 1) < ShiftCost(with, reader, inv_range, best, 1) ? refined : best;
}

// The largest joint's RMS q mismatch over its range when paired at `dt`, and that joint.
struct Mismatch {
  double worst = 0.0;
  int joint = 0;
};
Mismatch PositionMismatch(const JointSamples& with, const BaselineReader& reader, const Eigen::VectorXd& range,
                          double dt) {
  const int n = static_cast<int>(range.size());
  Eigen::VectorXd sum_sq = Eigen::VectorXd::Zero(n);
  int count = 0;
  BaselineReader::Point p;
  Eigen::VectorXd q_b(n);
  for (int i = 0; i < with.size(); ++i) {
    if (!reader.Locate(with.t[i] - with.t[0] + dt, &p)) continue;
    reader.Positions(p, &q_b);
    sum_sq += (with.q.row(i).transpose() - q_b).array().square().matrix();
    ++count;
  }
  Mismatch r;
  for (int j = 0; j < n && count > 0; ++j) {
    const double relative = std::sqrt(sum_sq[j] / count) / range[j];
    if (relative > r.worst) r.worst = relative, r.joint = j;
  }
  return r;
}

// The fit of `data` with only the payload free, and what the caller reports of it.
PayloadIdentification Fit(const RobotDynamics& model, const std::string& link, const JointSamples& data,
                          const PayloadIdentificationOptions& options) {
  PayloadIdentification r;
  r.link = link;
  r.body = PayloadBody(model, link);
  JointIdentificationOptions fit = options.fit;
  fit.frozen_bodies = AllButPayloadFrozen(model, r.body);
  fit.initial.resize(0);
  const JointNormalEquations eq = AccumulateNormalEquations(model, data);
  r.fit = IdentifyJointModel(model, eq, fit);
  // The stds also from time blocks (the residual's correlation and model error: fit_uncertainty.hpp).
  const TimeBlocks blocks = AccumulateTimeBlocks(model, data, r.fit.x);
  const FitUncertainty u = EstimateFitUncertainty(model, eq, r.fit.x, fit.prior_weight, fit.frozen_bodies, blocks);
  r.time_blocks = u.time_blocks;
  r.block_length = u.block_length;
  r.correlation_time = u.correlation_time;
  // The residual's sample-to-sample noise (file comment, "Model error").
  const Eigen::MatrixXd residual = PredictJointTorques(model, r.fit.x, data) - data.tau;
  const std::vector<int> pieces = SeamFreePieces(data);
  double sum_sq_diff = 0.0;
  long long diffs = 0;
  for (size_t p = 0; p + 1 < pieces.size(); ++p) {
    for (int i = pieces[p] + 1; i < pieces[p + 1]; ++i) {
      sum_sq_diff += (residual.row(i) - residual.row(i - 1)).squaredNorm();
      diffs += model.num_dofs();
    }
  }
  r.residual_white_noise = diffs > 0 ? std::sqrt(sum_sq_diff / (2.0 * diffs)) : 0.0;
  r.payload = model.BodyInertia(r.body, r.fit.x);
  r.plausibility = JudgeEstimatedBody(model.bodies()[r.body], r.fit.x.segment<10>(10 * r.body));
  if (r.plausibility) r.region = ToString(model.bodies()[r.body].region->source);
  r.uncertainty = u.bodies[r.body];
  r.held = u.body_held[r.body];
  r.noise_sigma = u.noise_sigma;
  r.num_samples = data.size();
  r.residual_rms = std::sqrt(r.fit.data_cost / std::max(1.0, double(data.size()) * model.num_dofs()));
  r.model_error = r.residual_rms > std::sqrt(2.0) * r.residual_white_noise;
  return r;
}

}  // namespace

int PayloadBody(const RobotDynamics& model, const std::string& link) {
  const std::string name = "payload@" + link;
  for (size_t e = 0; e < model.bodies().size(); ++e) {
    if (model.bodies()[e].name == name) return static_cast<int>(e);
  }
  throw std::invalid_argument("the model has no payload on link '" + link + "' (add the effect payload@" + link + ")");
}

PayloadIdentification IdentifyPayload(const RobotDynamics& model, const std::string& link,
                                      const JointSamples& with_payload, const PayloadIdentificationOptions& options) {
  CheckJoints(model, with_payload, "with-payload");
  return Fit(model, link, with_payload, options);
}

JointSamples PayloadDifferenceSamples(const RobotDynamics& model, const std::string& link,
                                      const JointSamples& with_payload, const JointSamples& baseline,
                                      double max_mismatch_torque, BaselinePairing* pairing) {
  if (!model.effects().empty()) {
    throw std::invalid_argument("the difference of two runs is fitted by the links and the payload alone: the "
                                "model must have no joint effects (they cancel in the difference)");
  }
  const int payload = PayloadBody(model, link);
  CheckJoints(model, with_payload, "with-payload");
  CheckJoints(model, baseline, "baseline");
  if (with_payload.size() < 2 || baseline.size() < 2) {
    throw std::invalid_argument("the with-payload and baseline logs need two samples each");
  }
  CheckTimes(with_payload, "with-payload");
  CheckTimes(baseline, "baseline");
  const int n = model.num_dofs();
  Eigen::VectorXd range(n);
  for (int j = 0; j < n; ++j) {
    range[j] = std::max(with_payload.q.col(j).maxCoeff() - with_payload.q.col(j).minCoeff(), 0.01);
  }
  const Eigen::VectorXd inv_range = range.cwiseInverse();
  const BaselineReader reader(baseline);
  BaselinePairing info;
  info.time_shift = BestShift(with_payload, reader, inv_range);
  const Mismatch unshifted = PositionMismatch(with_payload, reader, range, 0.0);
  const Mismatch shifted = PositionMismatch(with_payload, reader, range, info.time_shift);
  info.position_mismatch_unshifted = unshifted.worst;
  info.unshifted_joint = model.dof_names()[unshifted.joint];
  info.position_mismatch = shifted.worst;
  info.mismatch_joint = model.dof_names()[shifted.joint];
  // The pairs: with-payload sample i at s = t_i - t_0 with the baseline at its t_0 + s + dt.
  std::vector<int> rows;
  std::vector<BaselineReader::Point> points;
  for (int i = 0; i < with_payload.size(); ++i) {
    BaselineReader::Point p;
    if (reader.Locate(with_payload.t[i] - with_payload.t[0] + info.time_shift, &p)) {
      rows.push_back(i);
      points.push_back(p);
    }
  }
  const int m = static_cast<int>(rows.size());
  info.num_pairs = m;
  if (pairing != nullptr) *pairing = info;
  if (m < 2) throw std::invalid_argument("fewer than two with-payload samples lie within the baseline's duration");
  // w_links: the frozen links' coefficients (the model's at its priors, the payload's prior taken
  // out of its link's block).
  Eigen::VectorXd w_links = model.Coefficients(Eigen::VectorXd::Zero(model.num_parameters()));
  const EstimatedBody& body = model.bodies()[payload];
  w_links.segment<10>(10 * body.block) -= body.prior.vector();
  JointSamples out;
  out.joint_names = with_payload.joint_names;
  out.t.resize(m);
  out.q.resize(m, n);
  out.qd.resize(m, n);
  out.qdd.resize(m, n);
  out.tau.resize(m, n);
  double sum_mismatch = 0, sum_difference = 0;
  Eigen::VectorXd q_b(n), qd_b(n), qdd_b(n), tau_b(n);
  for (int p = 0; p < m; ++p) {
    const int i = rows[p];
    out.t[p] = with_payload.t[i];
    out.q.row(p) = with_payload.q.row(i);
    out.qd.row(p) = with_payload.qd.row(i);
    out.qdd.row(p) = with_payload.qdd.row(i);
    reader.Interpolate(baseline.q, points[p], &q_b);
    reader.Interpolate(baseline.qd, points[p], &qd_b);
    reader.Interpolate(baseline.qdd, points[p], &qdd_b);
    reader.Interpolate(baseline.tau, points[p], &tau_b);
    // tau = dtau + A(x_with) w_links = tau_with - tau_base + A(x_base) w_links (file comment).
    const Eigen::VectorXd links_base = model.InverseDynamicsFromCoefficients(w_links, q_b, qd_b, qdd_b);
    const Eigen::VectorXd links_with = model.InverseDynamicsFromCoefficients(
        w_links, out.q.row(p).transpose(), out.qd.row(p).transpose(), out.qdd.row(p).transpose());
    const Eigen::VectorXd tau = with_payload.tau.row(i).transpose() - tau_b + links_base;
    out.tau.row(p) = tau.transpose();
    sum_mismatch += (links_with - links_base).squaredNorm();
    sum_difference += (tau - links_with).squaredNorm();
  }
  info.mismatch_torque_rms = std::sqrt(sum_mismatch / (double(m) * n));
  info.difference_rms = std::sqrt(sum_difference / (double(m) * n));
  // No difference at all (the payload's torque is nil): any predicted mismatch is too much.
  info.mismatch_torque = sum_difference > 0 ? std::sqrt(sum_mismatch / sum_difference)
                                            : (sum_mismatch > 0 ? std::numeric_limits<double>::infinity() : 0.0);
  if (pairing != nullptr) *pairing = info;
  if (!(info.mismatch_torque <= max_mismatch_torque)) {
    throw std::invalid_argument(
        "the with-payload and baseline runs do not follow the same trajectory closely enough to be subtracted: "
        "paired at the best time shift (" + FormatNumber(1000 * info.time_shift, 4) + " ms), the links' torque "
        "that their remaining state mismatch predicts is " + FormatNumber(info.mismatch_torque_rms, 3) +
        " (N m or N) RMS, " + FormatNumber(info.mismatch_torque, 3) + " times the difference's " +
        FormatNumber(info.difference_rms, 3) + " (at most " + FormatNumber(max_mismatch_torque, 3) +
        ": the model's error in it, up to its size, could then be more than " +
        FormatNumber(100 * kTransportError * max_mismatch_torque, 3) + " % of the payload's torque); " + info.mismatch_joint + "'s positions differ by " +
        FormatNumber(100 * info.position_mismatch, 3) + " % of its range of motion " +
        FormatNumber(range[shifted.joint], 3) + " (rad or m) RMS; record the baseline with the same trajectory");
  }
  return out;
}

PayloadIdentification IdentifyPayloadFromDifference(const RobotDynamics& model, const std::string& link,
                                                    const JointSamples& with_payload, const JointSamples& baseline,
                                                    const PayloadIdentificationOptions& options) {
  BaselinePairing pairing;
  const JointSamples difference =
      PayloadDifferenceSamples(model, link, with_payload, baseline, options.max_mismatch_torque, &pairing);
  PayloadIdentification r = Fit(model, link, difference, options);
  r.from_difference = true;
  r.pairing = pairing;
  return r;
}

}  // namespace inertial
