#include "inertial/estimation/joint_diagnosis.hpp"

#include "inertial/estimation/explained_error.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <optional>
#include <set>
#include <stdexcept>
#include <thread>
#include <unordered_map>

namespace inertial {
namespace {

// The statistics of `eq` restricted to the features `index` (rows and columns).
JointNormalEquations Restrict(const JointNormalEquations& eq, const std::vector<int>& index) {
  const int F = static_cast<int>(index.size());
  JointNormalEquations out;
  out.AtA.resize(F, F);
  out.Atb.resize(F);
  for (int i = 0; i < F; ++i) {
    out.Atb[i] = eq.Atb[index[i]];
    for (int j = 0; j < F; ++j) out.AtA(i, j) = eq.AtA(index[i], index[j]);
  }
  out.btb = eq.btb;
  out.num_samples = eq.num_samples;
  return out;
}

std::vector<bool> FrozenBodies(const RobotDynamics& model, bool hold_links) {
  std::vector<bool> frozen(model.bodies().size(), false);
  if (!hold_links) return frozen;
  // Links are the estimated bodies named after a URDF link; rotors ("rotor@j") and payloads
  // ("payload@l") stay free.
  for (size_t e = 0; e < frozen.size(); ++e) frozen[e] = model.bodies()[e].name.find('@') == std::string::npos;
  return frozen;
}

// One model to fit on restricted statistics.
struct Job {
  std::optional<RobotDynamics> model;
  std::vector<int> features;  // into the catalog's features
  JointIdentificationOptions options;
  JointIdentificationResult fit;
  TorqueErrors validation;
};

void RunJob(Job* job, const JointNormalEquations& train, const std::vector<JointNormalEquations>& validation) {
  const JointNormalEquations eq = Restrict(train, job->features);
  if (job->options.initial.size() == 0) {
    job->options.initial = DefaultInitialParameters(*job->model, eq, job->options.frozen_bodies);
  }
  job->fit = IdentifyJointModel(*job->model, eq, job->options);
  std::vector<JointNormalEquations> v;
  v.reserve(validation.size());
  for (const JointNormalEquations& e : validation) v.push_back(Restrict(e, job->features));
  job->validation = ErrorsFromNormalEquations(v, job->model->Coefficients(job->fit.x));
}

void RunJobs(std::vector<Job>& jobs, const JointNormalEquations& train, const std::vector<JointNormalEquations>& validation,
             int threads) {
  if (threads <= 0) threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  threads = std::min<int>(threads, static_cast<int>(jobs.size()));
  std::atomic<int> next{0};
  std::exception_ptr error;
  std::atomic<bool> failed{false};
  auto worker = [&]() {
    for (int k = next++; k < static_cast<int>(jobs.size()) && !failed; k = next++) {
      try {
        RunJob(&jobs[k], train, validation);
      } catch (...) {
        if (!failed.exchange(true)) error = std::current_exception();
      }
    }
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) pool.emplace_back(worker);
  worker();
  for (std::thread& t : pool) t.join();
  if (error) std::rethrow_exception(error);
}

}  // namespace

TorqueErrors ErrorsFromNormalEquations(const std::vector<JointNormalEquations>& jointwise, const Eigen::VectorXd& w) {
  const int n = static_cast<int>(jointwise.size());
  if (n == 0 || jointwise[0].num_samples <= 0) throw std::invalid_argument("torque errors: no samples");
  TorqueErrors e;
  e.rms.resize(n);
  e.relative_rms.resize(n);
  const double N = jointwise[0].num_samples;
  double sse = 0.0, sst = 0.0;
  for (int k = 0; k < n; ++k) {
    const double s = SquaredError(jointwise[k], w);
    e.rms[k] = std::sqrt(s / N);
    // A joint whose measured torque is all zero has no relative error.
    e.relative_rms[k] = jointwise[k].btb > 0 ? e.rms[k] / std::sqrt(jointwise[k].btb / N) : std::nan("");
    sse += s;
    sst += jointwise[k].btb;
  }
  e.total_rms = std::sqrt(sse / (N * n));
  e.total_relative_rms = std::sqrt(sse / std::max(sst, 1e-300));
  return e;
}

JointDiagnosis DiagnoseJointModel(const RobotModelFactory& make, const std::vector<EffectSpec>& effects,
                                  const std::vector<std::string>& payload_links, const JointSamples& train,
                                  const JointSamples& validation, const JointDiagnosisOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  JointDiagnosis out;
  out.effects = effects;
  const RobotDynamics base = make(effects);
  if (static_cast<long>(train.size()) * base.num_dofs() < base.num_parameters()) {
    throw std::invalid_argument("diagnosis: " + std::to_string(train.size()) + " training samples give " +
                                std::to_string(static_cast<long>(train.size()) * base.num_dofs()) +
                                " torque equations, fewer than the model's " + std::to_string(base.num_parameters()) +
                                " parameters");
  }

  // The candidates: every catalog effect the model lacks.
  std::set<std::pair<EffectKind, std::string>> present;
  std::set<std::string> payloads_present;
  for (const EffectTerm& t : base.effects()) present.insert({t.kind, t.joint});
  for (const EffectSpec& s : effects) {
    if (s.kind == EffectKind::kPayload) payloads_present.insert(s.target);
  }
  std::vector<EffectSpec> candidates;
  for (const std::string& joint : base.dof_names()) {
    for (EffectKind kind : options.joint_kinds) {
      if (!IsJointEffect(kind) || present.count({kind, joint}) > 0) continue;
      EffectSpec s;
      s.kind = kind;
      s.target = joint;
      s.velocity_scale = options.coulomb_velocity_scale;
      s.text = std::string(ToString(kind)) + "@" + joint;
      candidates.push_back(s);
    }
  }
  if (options.hold_links) {
    for (const std::string& link : payload_links) {
      if (payloads_present.count(link) > 0) continue;
      EffectSpec s;
      s.kind = EffectKind::kPayload;
      s.target = link;
      s.text = "payload@" + link;
      candidates.push_back(s);
    }
  } else if (!payload_links.empty()) {
    out.notes.push_back(
        "payload candidates not tested: with free links a payload is indistinguishable from a change of its "
        "link's inertia, which the fit already identifies (hold the links at the URDF to test for payloads)");
  }

  // One model with every joint candidate: its features hold every model's features.
  std::vector<EffectSpec> catalog_effects = effects;
  for (const EffectSpec& s : candidates) {
    if (s.kind != EffectKind::kPayload) catalog_effects.push_back(s);
  }
  const RobotDynamics catalog = make(catalog_effects);
  std::unordered_map<std::string, int> catalog_index;
  const std::vector<std::string> catalog_names = catalog.FeatureNames();
  for (int f = 0; f < static_cast<int>(catalog_names.size()); ++f) catalog_index[catalog_names[f]] = f;
  auto features_of = [&](const RobotDynamics& m) {
    std::vector<int> index;
    for (const std::string& name : m.FeatureNames()) {
      const auto it = catalog_index.find(name);
      if (it == catalog_index.end()) throw std::logic_error("diagnosis: feature " + name + " not in the catalog");
      index.push_back(it->second);
    }
    return index;
  };
  const JointNormalEquations train_eq = AccumulateNormalEquations(catalog, train);
  const std::vector<JointNormalEquations> validation_eq = AccumulateJointwiseNormalEquations(catalog, validation);
  out.train_samples = train.size();
  out.validation_samples = validation.size();

  // The model itself.
  std::vector<Job> base_job(1);
  base_job[0].model.emplace(base);
  base_job[0].features = features_of(base);
  base_job[0].options = options.fit;
  base_job[0].options.frozen_bodies = FrozenBodies(base, options.hold_links);
  RunJobs(base_job, train_eq, validation_eq, 1);
  out.frozen_bodies = base_job[0].options.frozen_bodies;
  out.fit = base_job[0].fit;
  out.fit_validation = base_job[0].validation;
  {
    // The URDF's own prediction: its links alone (no payload or rotor priors, no effects).
    const RobotDynamics links = make({});
    std::vector<JointNormalEquations> v;
    for (const JointNormalEquations& e : validation_eq) v.push_back(Restrict(e, features_of(links)));
    out.prior_validation = ErrorsFromNormalEquations(v, links.Coefficients(Eigen::VectorXd::Zero(links.num_parameters())));
    out.fit_train = CompareTorques(PredictJointTorques(base, out.fit.x, train), train.tau);
  }
  if (!std::isfinite(out.fit_validation.total_rms) || !std::isfinite(out.prior_validation.total_rms)) {
    throw std::invalid_argument("diagnosis: the model's torques are not finite numbers (check gravity, units and "
                                "the data's magnitudes)");
  }

  if (!effects.empty()) {
    std::vector<Job> links(1);
    links[0].model.emplace(make({}));
    links[0].features = features_of(*links[0].model);
    links[0].options = options.fit;
    links[0].options.frozen_bodies = FrozenBodies(*links[0].model, options.hold_links);
    RunJobs(links, train_eq, validation_eq, 1);
    out.links_only_validation = links[0].validation;
  }

  // Each candidate on its own, warm-started from the model's fit.
  const std::vector<std::string> base_names = base.ParameterNames();
  std::unordered_map<std::string, double> base_x;
  for (int i = 0; i < static_cast<int>(base_names.size()); ++i) base_x[base_names[i]] = out.fit.x[i];
  std::vector<Job> jobs(candidates.size());
  for (size_t c = 0; c < candidates.size(); ++c) {
    std::vector<EffectSpec> with = effects;
    with.push_back(candidates[c]);
    Job& job = jobs[c];
    job.model.emplace(make(with));
    job.features = features_of(*job.model);
    job.options = options.fit;
    job.options.frozen_bodies = FrozenBodies(*job.model, options.hold_links);
    const JointNormalEquations eq = Restrict(train_eq, job.features);
    job.options.initial = DefaultInitialParameters(*job.model, eq, job.options.frozen_bodies);
    const std::vector<std::string> names = job.model->ParameterNames();
    for (int i = 0; i < static_cast<int>(names.size()); ++i) {
      const auto it = base_x.find(names[i]);
      if (it != base_x.end()) job.options.initial[i] = it->second;
    }
  }
  RunJobs(jobs, train_eq, validation_eq, options.threads);

  for (size_t c = 0; c < candidates.size(); ++c) {
    const Job& job = jobs[c];
    CandidateResult r;
    r.spec = candidates[c];
    r.name = candidates[c].text;
    (candidates[c].kind == EffectKind::kPayload ? r.link : r.joint) = candidates[c].target;
    r.validation = job.validation;
    r.explained = ExplainedShare(out.fit_validation.rms, job.validation.rms);
    r.converged = job.fit.lm.converged();
    r.iterations = job.fit.lm.iterations;
    if (candidates[c].kind == EffectKind::kPayload) {
      const int e = static_cast<int>(job.model->bodies().size()) - 1;  // the payload: the last body
      const Vector10 pi = job.model->BodyInertia(e, job.fit.x).vector();
      r.values.assign(pi.data(), pi.data() + 10);
    } else {
      r.values = job.model->EffectValues(static_cast<int>(job.model->effects().size()) - 1, job.fit.x);
    }
    out.candidates.push_back(std::move(r));
  }
  auto key = [](const CandidateResult& c) {
    const int p = c.spec.kind == EffectKind::kPayload ? 10 : (c.spec.kind == EffectKind::kSpring ? 2 : 1);
    return RankingKey(c.explained, p);
  };
  std::stable_sort(out.candidates.begin(), out.candidates.end(),
                   [&](const CandidateResult& a, const CandidateResult& b) { return key(a) > key(b); });
  // Suggestions first: every candidate at or above the threshold, in ranking order.
  const auto end = std::stable_partition(out.candidates.begin(), out.candidates.end(), [&](const CandidateResult& c) {
    return SupportedByHeldOutData(out.fit_validation, c.validation, c.explained, options.min_explained,
                                  options.min_gain);
  });
  out.num_suggestions = static_cast<int>(end - out.candidates.begin());
  if (!out.fit.lm.converged()) {
    out.num_suggestions = 0;
    out.notes.push_back("the model's own fit did not converge (" + std::string(ToString(out.fit.lm.reason)) + " after " +
                        std::to_string(out.fit.lm.iterations) +
                        " iterations): its candidates would all look good, so none is suggested; raise the iteration cap");
  }
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

JointDiagnosis IterateJointDiagnosis(const RobotModelFactory& make, const std::vector<EffectSpec>& effects,
                                     const std::vector<std::string>& payload_links, const JointSamples& train,
                                     const JointSamples& validation, const JointDiagnosisOptions& options,
                                     int max_steps, std::vector<DiagnosisStep>* steps) {
  const auto start = std::chrono::steady_clock::now();
  std::vector<EffectSpec> current = effects;
  JointDiagnosis d = DiagnoseJointModel(make, current, payload_links, train, validation, options);
  steps->clear();
  for (int step = 0; step < max_steps && d.num_suggestions > 0; ++step) {
    const CandidateResult& top = d.candidates[0];
    DiagnosisStep s;
    s.added = top.name;
    s.explained = top.explained;
    s.before = d.fit_validation;
    current.push_back(top.spec);
    d = DiagnoseJointModel(make, current, payload_links, train, validation, options);
    s.after = d.fit_validation;
    steps->push_back(s);
  }
  // links_only_validation is relative to the links, whatever was added.
  d.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return d;
}

void SplitHoldout(const JointSamples& data, double fraction, JointSamples* train, JointSamples* validation) {
  if (!(fraction > 0.0 && fraction < 1.0)) throw std::invalid_argument("holdout: the fraction must be in (0, 1)");
  const int N = data.size();
  const int held = static_cast<int>(std::lround(fraction * N));
  if (held < 2 || N - held < 2) {
    throw std::invalid_argument("holdout: " + std::to_string(N) + " samples cannot be split into two parts of at least 2");
  }
  auto part = [&](int begin, int count, JointSamples* out) {
    out->joint_names = data.joint_names;
    out->t = data.t.segment(begin, count);
    out->q = data.q.middleRows(begin, count);
    out->qd = data.qd.middleRows(begin, count);
    out->qdd = data.qdd.middleRows(begin, count);
    out->tau = data.tau.middleRows(begin, count);
  };
  part(0, N - held, train);
  part(N - held, held, validation);
}

}  // namespace inertial
