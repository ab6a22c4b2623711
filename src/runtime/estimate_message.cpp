#include "inertial/runtime/estimate_message.hpp"

#include <cmath>
#include <optional>

#include "inertial/estimate_t.hpp"
#include "inertial/estimation/parameter_layout.hpp"
#include "inertial/inertia/consistency.hpp"
#include "inertial/report/uncertainty_report.hpp"

namespace inertial {

namespace {

// One body's part of estimate_t.
inertial::body_estimate_t BodyEstimate(const std::string& name, const InertialParams& body, const Vector10* theta,
                                       const BodyUncertainty* uncertainty) {
  inertial::body_estimate_t b;
  b.name = name;
  const Vector10 pi = body.vector();
  for (int i = 0; i < 10; ++i) {
    b.pi[i] = pi[i];
    b.theta[i] = theta != nullptr ? (*theta)[i] : 0.0;
  }
  b.mass = body.mass();
  const Vector3 com = body.mass() > 0 ? body.com() : Vector3::Zero();
  for (int i = 0; i < 3; ++i) b.com[i] = com[i];
  b.mass_std = 0;
  for (int i = 0; i < 3; ++i) b.com_std[i] = 0;
  for (int i = 0; i < 6; ++i) b.inertia_std[i] = 0;
  if (uncertainty != nullptr && body.mass() > 0) {
    const BodyUncertainty& u = *uncertainty;
    b.mass_std = u.mass;
    for (int i = 0; i < 3; ++i) b.com_std[i] = u.com[i];
    for (int i = 0; i < 6; ++i) b.inertia_std[i] = u.inertia_about_com[i];  // about the COM, as estimate_t says
  }
  const ConsistencyReport c = CheckConsistency(body);
  b.min_triangle_margin = c.min_triangle_margin;
  b.min_pseudo_inertia_eigenvalue = c.min_pseudo_inertia_eigenvalue;
  b.physically_consistent = c.fully_consistent();
  return b;
}

void SetCounters(const SampleCounters& counters, std::uint64_t lost, inertial::estimate_t* m) {
  m->lost = static_cast<std::int64_t>(lost);
  m->num_unexcited = 0;  // a robot's encoder fills them in after
  m->unexcited.clear();
  m->received = static_cast<std::int64_t>(counters.received);
  m->accepted = static_cast<std::int64_t>(counters.accepted);
  m->dropped = static_cast<std::int64_t>(counters[Rejection::kQueueFull]);
  // rejected: every reason but the queue's (dropped has its own field), listed by name.
  m->rejected = static_cast<std::int64_t>(counters.total_rejected() - counters[Rejection::kQueueFull]);
  for (int k = 1; k < kNumRejections; ++k) {
    const Rejection r = static_cast<Rejection>(k);
    if (r == Rejection::kQueueFull || counters[r] == 0) continue;
    m->reject_reasons.emplace_back(ToString(r));
    m->reject_counts.push_back(static_cast<std::int64_t>(counters[r]));
  }
  m->num_reasons = static_cast<std::int32_t>(m->reject_reasons.size());
}

std::vector<std::uint8_t> Encode(const inertial::estimate_t& m) {
  std::vector<std::uint8_t> bytes(static_cast<size_t>(m.getEncodedSize()));
  m.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
  return bytes;
}

}  // namespace

std::vector<std::uint8_t> EncodeBodyEstimate(const OnlineBodyEstimator& est, const std::string& name, std::int64_t utime,
                                             const Eigen::VectorXd& residual_rms, double residual_window,
                                             const SampleCounters& counters, std::uint64_t lost) {
  inertial::estimate_t m;
  m.utime = utime;
  m.estimator = std::string(est.estimator().kind());
  const Eigen::VectorXd& x = est.estimator().parameters();
  const Eigen::MatrixXd P = est.estimator().Covariance();
  const bool per_body = m.estimator != "linear_rls";
  const Vector10 theta = per_body ? Vector10(x.head<10>()) : Vector10::Zero();
  const bool with_cov = per_body && P.rows() == x.size() && est.Body().mass() > 0;
  BodyUncertainty u;
  if (with_cov) u = UncertaintyOf(est.Body(), est.layout().BodyCovariance(0, x, P));
  m.bodies.push_back(BodyEstimate(name, est.Body(), per_body ? &theta : nullptr, with_cov ? &u : nullptr));
  m.num_bodies = 1;
  m.num_effects = 0;
  m.channel_names = {"mx", "my", "mz", "fx", "fy", "fz"};
  m.num_channels = 6;
  m.residual_rms.assign(residual_rms.data(), residual_rms.data() + residual_rms.size());
  m.residual_rms.resize(6, 0.0);
  m.residual_window = residual_window;
  SetCounters(counters, lost, &m);
  return Encode(m);
}

std::vector<std::uint8_t> EncodeEstimate(const OnlineJointEstimator& est, std::int64_t utime,
                                         const Eigen::VectorXd& residual_rms, double residual_window,
                                         const SampleCounters& counters, const std::vector<std::string>& unexcited,
                                         std::uint64_t lost) {
  const RobotDynamics& model = est.model();
  inertial::estimate_t m;
  m.utime = utime;
  m.estimator = std::string(ToString(est.kind()));
  const Eigen::VectorXd& x = est.estimator().parameters();
  const bool per_body = est.kind() != EstimatorKind::kLinearRls;
  // The same standard deviations as replay's and the model file's (uncertainty_report.hpp): each
  // body's in its report frame (a payload's in its link's frame).
  const std::optional<ModelUncertainty> uncertainty = per_body ? FromOnlineEstimator(est) : std::nullopt;
  for (int e = 0; e < static_cast<int>(model.bodies().size()); ++e) {
    const InertialParams body = est.Body(e);
    const Vector10 theta = per_body ? Vector10(x.segment<10>(10 * e)) : Vector10::Zero();
    m.bodies.push_back(BodyEstimate(model.bodies()[e].name, body, per_body ? &theta : nullptr,
                                    uncertainty && body.mass() > 0 ? &uncertainty->bodies[e] : nullptr));
  }
  m.num_bodies = static_cast<std::int32_t>(m.bodies.size());
  const std::vector<std::string> names = model.FeatureNames();
  const Eigen::VectorXd& w = est.coefficients();
  for (int f = model.num_inertia_features(); f < model.num_features(); ++f) {
    m.effect_names.push_back(names[f]);
    m.effect_values.push_back(w[f]);
  }
  m.num_effects = static_cast<std::int32_t>(m.effect_names.size());
  m.channel_names = model.dof_names();
  m.num_channels = static_cast<std::int32_t>(m.channel_names.size());
  m.residual_rms.assign(residual_rms.data(), residual_rms.data() + residual_rms.size());
  m.residual_rms.resize(m.channel_names.size(), 0.0);
  m.residual_window = residual_window;
  SetCounters(counters, lost, &m);
  m.unexcited = unexcited;
  m.num_unexcited = static_cast<std::int32_t>(m.unexcited.size());
  return Encode(m);
}


std::vector<std::uint8_t> EncodeEstimate(const SamplePipeline& pipeline, std::int64_t utime, const SampleCounters& counters,
                                         const std::vector<std::string>& unexcited, std::uint64_t lost) {
  const Eigen::VectorXd rms = pipeline.ResidualRms();
  return pipeline.body_mode()
             ? EncodeBodyEstimate(*pipeline.body(), "body", utime, rms, pipeline.residual_window_s(), counters, lost)
             : EncodeEstimate(*pipeline.robot(), utime, rms, pipeline.residual_window_s(), counters, unexcited, lost);
}

std::string CheckpointDescription(const OnlineJointEstimator& estimator) {
  std::string d = std::string(ToString(estimator.kind())) + " estimator; joints";
  for (const std::string& j : estimator.model().dof_names()) d += " " + j;
  d += "; parameters";
  for (const std::string& p : estimator.model().ParameterNames()) d += " " + p;
  return d;
}

std::string CheckpointDescription(const SamplePipeline& pipeline) {
  if (pipeline.body_mode()) return std::string(pipeline.estimator().kind()) + " estimator; single body";
  return CheckpointDescription(*pipeline.robot());
}

}  // namespace inertial
