#include "inertial/diagnosis/payload_identification.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

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
  const FitUncertainty u = EstimateFitUncertainty(model, eq, r.fit.x, fit.prior_weight, fit.frozen_bodies);
  r.payload = model.BodyInertia(r.body, r.fit.x);
  r.uncertainty = u.bodies[r.body];
  r.held = u.body_held[r.body];
  r.noise_sigma = u.noise_sigma;
  r.num_samples = data.size();
  r.residual_rms = std::sqrt(r.fit.data_cost / std::max(1.0, double(data.size()) * model.num_dofs()));
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
                                      double max_position_mismatch, double* mismatch, std::string* joint) {
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
  const int n = model.num_dofs();
  // Pairs: with-payload sample i at s = t_i - t_0 with the baseline interpolated at its t_0 + s.
  std::vector<int> rows;
  std::vector<Eigen::VectorXd> q_base, tau_base;
  const double s_end = baseline.t[baseline.size() - 1] - baseline.t[0];
  int k = 0;  // baseline interval [k, k + 1]
  for (int i = 0; i < with_payload.size(); ++i) {
    const double s = with_payload.t[i] - with_payload.t[0];
    if (s > s_end) break;
    const double t = baseline.t[0] + s;
    while (k + 2 < baseline.size() && baseline.t[k + 1] < t) ++k;
    const double a = std::clamp((t - baseline.t[k]) / (baseline.t[k + 1] - baseline.t[k]), 0.0, 1.0);
    rows.push_back(i);
    q_base.push_back(((1 - a) * baseline.q.row(k) + a * baseline.q.row(k + 1)).transpose());
    tau_base.push_back(((1 - a) * baseline.tau.row(k) + a * baseline.tau.row(k + 1)).transpose());
  }
  const int m = static_cast<int>(rows.size());
  if (m < 2) throw std::invalid_argument("fewer than two with-payload samples lie within the baseline's duration");
  // The position check (file comment).
  Eigen::VectorXd sum_sq = Eigen::VectorXd::Zero(n);
  for (int p = 0; p < m; ++p) sum_sq += (with_payload.q.row(rows[p]).transpose() - q_base[p]).array().square().matrix();
  double worst = 0;
  int worst_joint = 0;
  Eigen::VectorXd rms(n), range(n);
  for (int j = 0; j < n; ++j) {
    rms[j] = std::sqrt(sum_sq[j] / m);
    range[j] = std::max(with_payload.q.col(j).maxCoeff() - with_payload.q.col(j).minCoeff(), 0.01);
    if (rms[j] / range[j] > worst) {
      worst = rms[j] / range[j];
      worst_joint = j;
    }
  }
  if (mismatch != nullptr) *mismatch = worst;
  if (joint != nullptr) *joint = model.dof_names()[worst_joint];
  if (!(worst <= max_position_mismatch)) {
    throw std::invalid_argument(
        "the with-payload and baseline runs do not follow the same trajectory: " + model.dof_names()[worst_joint] +
        "'s positions differ by " + FormatNumber(rms[worst_joint], 3) + " (rad or m) RMS at the same time since start, " +
        FormatNumber(100 * worst, 3) + " % of its range of motion " + FormatNumber(range[worst_joint], 3) +
        " (at most " + FormatNumber(100 * max_position_mismatch, 3) +
        " %); record the baseline with the same trajectory, started the same way");
  }
  // tau = dtau + A w_links: the frozen links' torque (the model's coefficients at its priors, the
  // payload's prior taken out of its link's block) at the with-run's state.
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
  for (int p = 0; p < m; ++p) {
    const int i = rows[p];
    out.t[p] = with_payload.t[i];
    out.q.row(p) = with_payload.q.row(i);
    out.qd.row(p) = with_payload.qd.row(i);
    out.qdd.row(p) = with_payload.qdd.row(i);
    const Eigen::VectorXd tau_links = model.InverseDynamicsFromCoefficients(
        w_links, out.q.row(p).transpose(), out.qd.row(p).transpose(), out.qdd.row(p).transpose());
    out.tau.row(p) = (with_payload.tau.row(i).transpose() - tau_base[p] + tau_links).transpose();
  }
  return out;
}

PayloadIdentification IdentifyPayloadFromDifference(const RobotDynamics& model, const std::string& link,
                                                    const JointSamples& with_payload, const JointSamples& baseline,
                                                    const PayloadIdentificationOptions& options) {
  double mismatch = 0;
  std::string joint;
  const JointSamples difference = PayloadDifferenceSamples(model, link, with_payload, baseline,
                                                           options.max_position_mismatch, &mismatch, &joint);
  PayloadIdentification r = Fit(model, link, difference, options);
  r.from_difference = true;
  r.position_mismatch = mismatch;
  r.mismatch_joint = joint;
  return r;
}

}  // namespace inertial
