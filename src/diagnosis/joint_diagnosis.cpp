#include "inertial/diagnosis/joint_diagnosis.hpp"
#include "inertial/signal/sample_selection.hpp"

#include <Eigen/Cholesky>

#include "inertial/diagnosis/candidate_ranking.hpp"
#include "inertial/diagnosis/explained_error.hpp"
#include "inertial/estimation/fit_uncertainty.hpp"
#include "inertial/diagnosis/friction_shape.hpp"
#include "inertial/estimation/batch/robust_identification.hpp"
#include "inertial/signal/trajectory_overlap.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <limits>
#include <map>
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

// Links are the estimated bodies named after a URDF link; rotors ("rotor@j") and payloads
// ("payload@l") are not.
std::vector<bool> LinkBodies(const RobotDynamics& model) {
  std::vector<bool> links(model.bodies().size(), false);
  for (size_t e = 0; e < links.size(); ++e) links[e] = model.bodies()[e].name.find('@') == std::string::npos;
  return links;
}

// hold_links: every link held at its URDF; else only `held_link` (a payload candidate's link), if any.
// The links a payload among `effects` holds at their URDF: with free links, a link and a payload
// on it would share the link's regressor columns (only the regularizer would split them), so the
// payload carries the departure from the URDF, as when it was judged as a candidate.
std::set<std::string> HeldLinks(const std::vector<EffectSpec>& effects) {
  std::set<std::string> held;
  for (const EffectSpec& e : effects) {
    if (e.kind == EffectKind::kPayload) held.insert(e.target);
  }
  return held;
}

// hold_links: every link held at its URDF; else only the links in `held` (payload candidates' links).
std::vector<bool> FrozenBodies(const RobotDynamics& model, bool hold_links, const std::set<std::string>& held = {}) {
  std::vector<bool> frozen = LinkBodies(model);
  for (size_t e = 0; e < frozen.size(); ++e) {
    frozen[e] = frozen[e] && (hold_links || held.count(model.bodies()[e].name) > 0);
  }
  return frozen;
}

// A candidate's parameters fitted to the data: its coefficients and, for the friction shapes, the
// shape fitted before it (friction_shape.hpp).
int CandidateParameters(EffectKind kind) {
  return kind == EffectKind::kPayload ? 10 : NumEffectValues(kind) + FrictionShapeParameters(kind);
}


// Dry-friction forms: one per joint. A richer form replaces a simpler one present on its joint
// (coulomb -> asymmetric or sigmoid) instead of joining it: stacked on one joint their features
// are nearly collinear (a sigmoid of zero shift is half a Coulomb step; Coulomb is the asymmetric
// form with equal levels), and their coefficients undetermined.
bool IsDryFriction(EffectKind kind) {
  return kind == EffectKind::kCoulomb || kind == EffectKind::kAsymmetric || kind == EffectKind::kSigmoid;
}

// The effects with every joint effect stated for all joints (no target) written out per joint, so
// that one joint's term can be replaced.
std::vector<EffectSpec> PerJoint(const std::vector<EffectSpec>& effects, const std::vector<std::string>& joints) {
  std::vector<EffectSpec> out;
  for (const EffectSpec& e : effects) {
    if (!IsJointEffect(e.kind) || !e.target.empty()) {
      out.push_back(e);
      continue;
    }
    for (const std::string& j : joints) {
      EffectSpec one = e;
      one.target = j;
      one.text = std::string(ToString(e.kind)) + "@" + j;
      out.push_back(one);
    }
  }
  return out;
}

// `effects` with `candidate` added, replacing the dry-friction form it replaces (if any).
std::vector<EffectSpec> WithCandidate(const std::vector<EffectSpec>& effects, const std::vector<std::string>& joints,
                                      const EffectSpec& candidate, const std::optional<EffectSpec>& replaced) {
  std::vector<EffectSpec> with = replaced ? PerJoint(effects, joints) : effects;
  if (replaced) {
    with.erase(std::remove_if(with.begin(), with.end(),
                              [&](const EffectSpec& e) { return e.kind == replaced->kind && e.target == replaced->target; }),
               with.end());
  }
  with.push_back(candidate);
  return with;
}

// Every estimated body of the fit against its prior, both in the body's report frame.
std::vector<BodyPlausibility> PlausibilityOf(const RobotDynamics& model, const JointNormalEquations& eq,
                                             const Eigen::VectorXd& x, const JointIdentificationOptions& options,
                                             double tolerance, std::vector<BodyUncertainty>* stds) {
  // Margins only shrink departures: the uncertainty (one P x P decomposition) is needed only when
  // some link departs beyond the tolerance by its estimate alone.
  // A payload's own standard deviations are reported: always needed with one.
  bool needed = false;
  for (size_t e = 0; e < model.bodies().size() && !needed; ++e) {
    if (!options.frozen_bodies.empty() && options.frozen_bodies[e]) continue;
    if (model.bodies()[e].name.rfind("payload@", 0) == 0) {
      needed = true;
      break;
    }
    Eigen::VectorXd x_prior = x;
    x_prior.segment<10>(10 * static_cast<int>(e)).setZero();
    try {
      needed = !MeasurePlausibility(model.BodyInertia(static_cast<int>(e), x),
                                    model.BodyInertia(static_cast<int>(e), x_prior))
                    .Within(tolerance);
    } catch (const std::invalid_argument&) {
      needed = true;
    }
  }
  FitUncertainty u;
  try {
    if (needed) u = EstimateFitUncertainty(model, eq, x, options.prior_weight, options.frozen_bodies);
  } catch (const std::invalid_argument&) {
    // No residual degrees of freedom: no margins.
  }
  *stds = u.bodies;
  std::vector<BodyPlausibility> out;
  for (size_t e = 0; e < model.bodies().size(); ++e) {
    const int i = static_cast<int>(e);
    Eigen::VectorXd x_prior = x;
    x_prior.segment<10>(10 * i).setZero();
    const InertialParams prior = model.BodyInertia(i, x_prior);
    DepartureMargins margins;
    // Whether the data establish a departure: the fit's own stds, without the CAD spread's floor
    // that a held quantity reports (fit_uncertainty.hpp).
    if (e < u.bodies_from_fit.size() && e < u.body_pi_covariance.size()) {
      margins = DepartureMarginsOf(prior, u.bodies_from_fit[e], u.body_pi_covariance[e]);
    }
    try {
      out.push_back(MeasurePlausibility(model.BodyInertia(i, x), prior, margins));
    } catch (const std::invalid_argument&) {
      // A body at the edge of the map's range (pi not finite or singular): as implausible as can be.
      BodyPlausibility p;
      p.factor = p.raw_factor = std::numeric_limits<double>::infinity();
      p.divergence = std::numeric_limits<double>::infinity();
      out.push_back(p);
    }
  }
  return out;
}

// One model to fit on restricted statistics.
struct Job {
  std::optional<RobotDynamics> model;
  std::vector<int> features;  // into the catalog's features
  JointIdentificationOptions options;
  JointIdentificationResult fit;
  TorqueErrors validation;
  std::vector<BodyPlausibility> plausibility;
  std::vector<BodyUncertainty> stds;  // per estimated body (empty without residual degrees of freedom)
  double tolerance = kDefaultPriorTolerance;
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
  job->plausibility = PlausibilityOf(*job->model, eq, job->fit.x, job->options, job->tolerance, &job->stds);
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

namespace {

// What every diagnosis of one pair of logs shares: the statistics of a model holding every
// candidate (its features hold every model's), the noise's correlation time, the retrace share.
// IterateJointDiagnosis computes it once for all its steps (each step's models are sub-models of
// the first step's catalog).
struct Prepared {
  // The friction shapes of the candidates, per (kind, joint), fitted once (FitFrictionShapes).
  std::map<std::pair<EffectKind, std::string>, FrictionShape> shapes;
  std::map<std::string, double> shape_variance;  // per joint: the residual's variance left by the best shape
  bool shapes_fitted = false;
  std::optional<RobotDynamics> catalog;
  std::unordered_map<std::string, int> index;
  JointNormalEquations train_eq;                     // the sum of train_jointwise
  std::vector<JointNormalEquations> train_jointwise;  // per joint: the training RMS without a data pass
  std::vector<JointNormalEquations> validation_eq;
  Eigen::VectorXd residual_tau;
  double retraced = 0.0;
};

// The residual of a model holding the links (free, linear least squares), the model's effects and
// viscous friction and an offset on every joint, on at most kShapeSamples training samples evenly
// spaced (a shape is three numbers at most; the levels are fitted later on every sample); then the
// shape of every friction kind asked for, per joint (friction_shape.hpp).
void FitFrictionShapes(const RobotModelFactory& make, const std::vector<EffectSpec>& effects,
                       const std::vector<EffectKind>& kinds, const JointSamples& train, Prepared* p) {
  constexpr int kShapeSamples = 4000;
  p->shapes_fitted = true;
  std::vector<EffectKind> shaped;
  for (EffectKind k : kinds) {
    if (FrictionShapeParameters(k) > 0) shaped.push_back(k);
  }
  if (shaped.empty()) return;
  const RobotDynamics base = make(effects);
  std::set<std::pair<EffectKind, std::string>> present;
  for (const EffectTerm& t : base.effects()) present.insert({t.kind, t.joint});
  std::vector<EffectSpec> with = effects;
  for (const std::string& joint : base.dof_names()) {
    for (EffectKind k : {EffectKind::kViscous, EffectKind::kOffset}) {
      if (present.count({k, joint}) > 0) continue;
      EffectSpec s;
      s.kind = k;
      s.target = joint;
      s.text = std::string(ToString(k)) + "@" + joint;
      with.push_back(s);
    }
  }
  const RobotDynamics model = make(with);
  const int stride = std::max(1, (train.size() + kShapeSamples - 1) / kShapeSamples);
  const JointSamples sub = SelectSamples(train, RowRange(0, train.size(), stride));
  const int N = sub.size(), n = model.num_dofs();
  const JointNormalEquations eq = AccumulateNormalEquations(model, sub);
  Eigen::MatrixXd H = eq.AtA;
  H.diagonal() += 1e-9 * H.diagonal().cwiseAbs().cwiseMax(1e-300);
  const Eigen::VectorXd w = H.ldlt().solve(eq.Atb);
  if (!w.allFinite()) return;  // non-finite data: no shapes (the diagnosis refuses such data later)
  Eigen::MatrixXd residual(N, n);
  Eigen::MatrixXd A(n, model.num_features());
  TreeWorkspace workspace = model.MakeWorkspace();
  for (int i = 0; i < N; ++i) {
    model.Features(sub.q.row(i).transpose(), sub.qd.row(i).transpose(), sub.qdd.row(i).transpose(), &workspace, A);
    residual.row(i) = sub.tau.row(i) - (A * w).transpose();
  }
  if (!residual.allFinite() || !sub.qd.allFinite()) return;
  for (int j = 0; j < n; ++j) {
    const std::string& joint = model.dof_names()[j];
    double best = 0.0;
    for (EffectKind k : shaped) {
      if (present.count({k, joint}) > 0) continue;
      const FrictionShape shape = FitFrictionShape(k, joint, sub.qd.col(j), residual.col(j));
      p->shapes[{k, joint}] = shape;
      best = std::max(best, shape.gain);
    }
    p->shape_variance[joint] = std::max(0.0, residual.col(j).squaredNorm() - best) / N;
  }
}

// A friction candidate of a shape: coulomb with its fitted scale (the default where no shape helps);
// the asymmetric and sigmoid forms only where their shape explains more of the residual than the
// symmetric Coulomb step does by at least 2 residual variances per extra parameter (Akaike's
// penalty: a screen that keeps any shape the judgement could accept and drops the joints whose
// friction is symmetric, each of which would cost a fit).
std::optional<EffectSpec> ShapedCandidate(const Prepared& p, EffectKind kind, const std::string& joint,
                                          const EffectSpec& fallback) {
  const auto it = p.shapes.find({kind, joint});
  if (it == p.shapes.end() || !(it->second.gain > 0.0)) {
    if (kind == EffectKind::kCoulomb) return fallback;
    return std::nullopt;
  }
  if (kind != EffectKind::kCoulomb) {
    const auto coulomb = p.shapes.find({EffectKind::kCoulomb, joint});
    const double symmetric = coulomb == p.shapes.end() ? 0.0 : coulomb->second.gain;
    const auto variance = p.shape_variance.find(joint);
    const int extra = CandidateParameters(kind) - CandidateParameters(EffectKind::kCoulomb);
    if (variance == p.shape_variance.end() || it->second.gain - symmetric < 2.0 * extra * variance->second) {
      return std::nullopt;
    }
  }
  EffectSpec s = it->second.spec;
  s.text = std::string(ToString(kind)) + "@" + joint;
  return s;
}

// Rows [begin, begin + count) of a log.
// Per-joint statistics of a log: blocks of kBlock samples, each accumulated by whichever thread is
// free, summed in block order, so that the result does not depend on the number of threads (the
// diagnosis's choices must not change with the machine). Each thread copies one block at a time.
std::vector<JointNormalEquations> JointwiseInParallel(const RobotDynamics& model, const JointSamples& data, int threads) {
  constexpr int kBlock = 4096;
  const int blocks = std::max(1, (data.size() + kBlock - 1) / kBlock);
  if (data.size() <= kBlock) return AccumulateJointwiseNormalEquations(model, data);
  threads = std::max(1, std::min(threads, blocks));
  std::vector<std::vector<JointNormalEquations>> parts(blocks);
  std::vector<std::exception_ptr> errors(blocks);
  std::atomic<int> next{0};
  auto worker = [&]() {
    for (int k = next++; k < blocks; k = next++) {
      try {
        const int begin = k * kBlock, count = std::min(kBlock, data.size() - begin);
        parts[k] = AccumulateJointwiseNormalEquations(model, SelectSamples(data, RowRange(begin, begin + count)));
      } catch (...) {
        errors[k] = std::current_exception();
      }
    }
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) pool.emplace_back(worker);
  worker();
  for (std::thread& t : pool) t.join();
  for (const std::exception_ptr& e : errors) {
    if (e) std::rethrow_exception(e);
  }
  std::vector<JointNormalEquations> sum = parts[0];
  for (int k = 1; k < blocks; ++k) {
    for (size_t j = 0; j < sum.size(); ++j) {
      sum[j].AtA += parts[k][j].AtA;
      sum[j].Atb += parts[k][j].Atb;
      sum[j].btb += parts[k][j].btb;
      sum[j].num_samples += parts[k][j].num_samples;
    }
  }
  return sum;
}

void PrepareStatistics(const RobotModelFactory& make, const std::vector<EffectSpec>& catalog_effects,
                       const JointSamples& train, const JointSamples& validation, int threads, Prepared* out) {
  Prepared& p = *out;
  p.catalog.emplace(make(catalog_effects));
  const RobotDynamics& catalog = *p.catalog;
  const std::vector<std::string> names = catalog.FeatureNames();
  for (int f = 0; f < static_cast<int>(names.size()); ++f) p.index[names[f]] = f;
  p.train_jointwise = JointwiseInParallel(catalog, train, threads);
  p.train_eq = p.train_jointwise[0];
  for (size_t k = 1; k < p.train_jointwise.size(); ++k) {
    p.train_eq.AtA += p.train_jointwise[k].AtA;
    p.train_eq.Atb += p.train_jointwise[k].Atb;
    p.train_eq.btb += p.train_jointwise[k].btb;
  }
  p.validation_eq = JointwiseInParallel(catalog, validation, threads);
  // The residual's correlation time (candidate_evidence.hpp) is that of the noise: measured on what
  // the most complete model leaves (every candidate, links free, linear least squares on the
  // training data), since the model's own residual is coloured by the very effects it lacks.
  Eigen::MatrixXd H = p.train_eq.AtA;
  H.diagonal() += 1e-9 * H.diagonal().cwiseAbs().cwiseMax(1e-300);
  const Eigen::VectorXd w_catalog = H.ldlt().solve(p.train_eq.Atb);
  const int n = catalog.num_dofs();
  Eigen::MatrixXd residual(validation.size(), n);
  Eigen::MatrixXd A(n, catalog.num_features());
  TreeWorkspace workspace = catalog.MakeWorkspace();
  for (int i = 0; i < validation.size(); ++i) {
    catalog.Features(validation.q.row(i).transpose(), validation.qd.row(i).transpose(),
                     validation.qdd.row(i).transpose(), &workspace, A);
    residual.row(i) = (A * w_catalog - validation.tau.row(i).transpose()).transpose();
  }
  p.residual_tau.resize(n);
  for (int j = 0; j < n; ++j) p.residual_tau[j] = IntegratedAutocorrelationTime(residual.col(j));
  p.retraced = RetracedShare(train, validation);
}

// The candidates of one diagnosis: every catalog effect the model lacks (payloads on the links the
// options name when links are held; with free links they come after the model's fit).
struct CandidateList {
  std::vector<EffectSpec> specs;
  std::vector<std::optional<EffectSpec>> replaces;  // per candidate: the friction form it replaces
  std::set<std::string> payloads_present;
};

EffectSpec PayloadCandidate(const std::string& link) {
  EffectSpec s;
  s.kind = EffectKind::kPayload;
  s.target = link;
  s.text = "payload@" + link;
  return s;
}

CandidateList ListCandidates(const RobotDynamics& base, const std::vector<EffectSpec>& effects,
                             const std::vector<std::string>& payload_links, const JointDiagnosisOptions& options,
                             const Prepared& data) {
  CandidateList list;
  std::set<std::pair<EffectKind, std::string>> present;
  for (const EffectTerm& t : base.effects()) present.insert({t.kind, t.joint});
  for (const EffectSpec& s : effects) {
    if (s.kind == EffectKind::kPayload) list.payloads_present.insert(s.target);
  }
  // The dry-friction form present on each joint (at most one is ever added; a user's list may
  // hold more, and then no other is offered there).
  std::map<std::string, EffectSpec> friction_of;
  std::set<std::string> friction_stacked;
  for (const EffectSpec& e : PerJoint(effects, base.dof_names())) {
    if (!IsDryFriction(e.kind)) continue;
    if (!friction_of.emplace(e.target, e).second) friction_stacked.insert(e.target);
  }
  for (const std::string& joint : base.dof_names()) {
    for (EffectKind kind : options.joint_kinds) {
      if (!IsJointEffect(kind) || present.count({kind, joint}) > 0) continue;
      std::optional<EffectSpec> replaced;
      if (IsDryFriction(kind)) {
        const auto it = friction_of.find(joint);
        if (it != friction_of.end()) {
          // Only a richer form replaces Coulomb's step; nothing replaces a richer form.
          if (it->second.kind != EffectKind::kCoulomb || friction_stacked.count(joint) > 0) continue;
          replaced = it->second;
        }
      }
      EffectSpec s;
      s.kind = kind;
      s.target = joint;
      s.velocity_scale = options.coulomb_velocity_scale;
      s.text = std::string(ToString(kind)) + "@" + joint;
      if (FrictionShapeParameters(kind) > 0) {
        const std::optional<EffectSpec> shaped = ShapedCandidate(data, kind, joint, s);
        if (!shaped) continue;
        s = *shaped;
      }
      list.specs.push_back(s);
      list.replaces.push_back(replaced);
    }
  }
  if (options.hold_links) {
    for (const std::string& link : payload_links) {
      if (list.payloads_present.count(link) == 0) {
        list.specs.push_back(PayloadCandidate(link));
        list.replaces.emplace_back();
      }
    }
  }
  return list;
}

// Every candidate model must be determined by the training data: more torque equations than the
// parameters of the largest one (the model with a payload or a spring added).
void CheckDetermined(const RobotDynamics& base, const CandidateList& list, int train_samples,
                     const JointDiagnosisOptions& options) {
  int largest = 0;
  for (const EffectSpec& c : list.specs) largest = std::max(largest, CandidateParameters(c.kind));
  if (options.hold_links || options.payloads) largest = std::max(largest, CandidateParameters(EffectKind::kPayload));
  const long equations = static_cast<long>(train_samples) * base.num_dofs();
  if (equations <= base.num_parameters() + largest) {
    throw std::invalid_argument("diagnosis: " + std::to_string(train_samples) + " training samples give " +
                                std::to_string(equations) + " torque equations, too few for the " +
                                std::to_string(base.num_parameters() + largest) +
                                " parameters of the largest model tested (give a longer log)");
  }
}

std::unordered_map<std::string, double> NamedParameters(const RobotDynamics& m, const Eigen::VectorXd& x) {
  std::unordered_map<std::string, double> v;
  const std::vector<std::string> names = m.ParameterNames();
  for (int i = 0; i < static_cast<int>(names.size()); ++i) v[names[i]] = x[i];
  return v;
}

// How the models of one diagnosis are set up and fitted on the prepared statistics.
struct Fitter {
  const RobotModelFactory& make;
  const JointDiagnosisOptions& options;
  const Prepared& data;

  std::vector<int> FeaturesOf(const RobotDynamics& m) const {
    std::vector<int> index;
    for (const std::string& name : m.FeatureNames()) {
      const auto it = data.index.find(name);
      if (it == data.index.end()) throw std::logic_error("diagnosis: feature " + name + " not in the catalog");
      index.push_back(it->second);
    }
    return index;
  }
  // `model` with `effects` (its payloads' links held), with the options' fit.
  void Setup(Job& job, const RobotDynamics& model, const std::vector<EffectSpec>& with) const {
    job.model.emplace(model);
    job.features = FeaturesOf(*job.model);
    job.options = options.fit;
    job.tolerance = options.prior_tolerance;
    job.options.frozen_bodies = FrozenBodies(*job.model, options.hold_links, HeldLinks(with));
  }
  // The model with `with`, warm-started from the parameters `warm` names.
  void SetupWarm(Job& job, const std::vector<EffectSpec>& with, const std::unordered_map<std::string, double>& warm) const {
    Setup(job, make(with), with);
    const JointNormalEquations eq = Restrict(data.train_eq, job.features);
    job.options.initial = DefaultInitialParameters(*job.model, eq, job.options.frozen_bodies);
    const std::vector<std::string> names = job.model->ParameterNames();
    for (int i = 0; i < static_cast<int>(names.size()); ++i) {
      const auto it = warm.find(names[i]);
      if (it == warm.end()) continue;
      // A held link stays at its URDF (theta = 0), whatever the warm start says.
      const std::vector<bool>& frozen = job.options.frozen_bodies;
      const bool held = i < 10 * static_cast<int>(frozen.size()) && frozen[i / 10];
      job.options.initial[i] = held ? 0.0 : it->second;
    }
  }
  void Run(std::vector<Job>& jobs, int threads) const { RunJobs(jobs, data.train_eq, data.validation_eq, threads); }
};

// The model itself, and (when it has effects) the links alone, fitted side by side; the model's
// plausibility, reference errors and notes into `out`.
void FitTheModel(const Fitter& fitter, const RobotDynamics& base, const std::vector<EffectSpec>& effects, int threads,
                 JointDiagnosis* out) {
  const JointDiagnosisOptions& options = fitter.options;
  std::vector<Job> base_job(effects.empty() ? 1 : 2);
  fitter.Setup(base_job[0], base, effects);
  if (!effects.empty()) fitter.Setup(base_job[1], fitter.make({}), {});
  fitter.Run(base_job, threads);
  out->frozen_bodies = base_job[0].options.frozen_bodies;
  out->fit = base_job[0].fit;
  out->fit_validation = base_job[0].validation;
  out->plausibility = base_job[0].plausibility;
  out->links = LinkBodies(base);
  for (const EstimatedBody& b : base.bodies()) out->body_names.push_back(b.name);
  out->implausibility = LinksImplausibility(out->plausibility, out->links, options.prior_tolerance);
  out->residual_tau = fitter.data.residual_tau;
  out->retraced = fitter.data.retraced;
  if (out->retraced >= kRetracedShare) {
    out->notes.push_back(std::to_string(static_cast<int>(std::lround(100 * out->retraced))) +
                         " % of the held-out samples retrace the training trajectory (within 1 % of every joint's "
                         "range of q and qd): this validation cannot reveal effects that only fit this excitation; "
                         "validate on a different trajectory");
  }
  {
    // The URDF's own prediction: its links alone (no payload or rotor priors, no effects).
    const RobotDynamics links = fitter.make({});
    std::vector<JointNormalEquations> v;
    for (const JointNormalEquations& e : fitter.data.validation_eq) v.push_back(Restrict(e, fitter.FeaturesOf(links)));
    out->prior_validation =
        ErrorsFromNormalEquations(v, links.Coefficients(Eigen::VectorXd::Zero(links.num_parameters())));
    std::vector<JointNormalEquations> t;
    for (const JointNormalEquations& e : fitter.data.train_jointwise) t.push_back(Restrict(e, fitter.FeaturesOf(base)));
    out->fit_train = ErrorsFromNormalEquations(t, base.Coefficients(out->fit.x));
  }
  if (!std::isfinite(out->fit_validation.total_rms) || !std::isfinite(out->prior_validation.total_rms)) {
    throw std::invalid_argument("diagnosis: the model's torques are not finite numbers (check gravity, units and "
                                "the data's magnitudes)");
  }
  if (!effects.empty()) out->links_only_validation = base_job[1].validation;
}

// Free links: a link the fit bends beyond the tolerance may carry a payload.
void AddBentLinkPayloads(const RobotDynamics& base, const std::vector<std::string>& payload_links,
                         const JointDiagnosisOptions& options, const JointDiagnosis& out, CandidateList* list) {
  if (options.hold_links || !options.payloads) return;
  const std::set<std::string> allowed(payload_links.begin(), payload_links.end());
  for (size_t e = 0; e < base.bodies().size(); ++e) {
    const std::string& name = base.bodies()[e].name;
    if (out.links[e] && !out.plausibility[e].Within(options.prior_tolerance) && allowed.count(name) > 0 &&
        list->payloads_present.count(name) == 0) {
      list->specs.push_back(PayloadCandidate(name));
      list->replaces.emplace_back();
    }
  }
}

// A candidate's evidence against the model `without` (held-out errors, links' implausibility) from
// its fitted job. A replacement adds the parameters its form has beyond the one it replaces.
void JudgeJob(const Job& job, const EffectSpec& spec, const std::optional<EffectSpec>& replaced,
              const TorqueErrors& without, double b_without, const Eigen::VectorXd& residual_tau, int samples,
              const JointDiagnosisOptions& options, CandidateResult* r) {
  EvidenceRules rules;
  rules.min_explained = options.min_explained;
  rules.min_gain = options.min_gain;
  rules.prior_tolerance = options.prior_tolerance;
  r->validation = job.validation;
  r->plausibility = job.plausibility;
  r->implausibility = LinksImplausibility(job.plausibility, LinkBodies(*job.model), options.prior_tolerance);
  const int added = CandidateParameters(spec.kind) - (replaced ? CandidateParameters(replaced->kind) : 0);
  r->evidence = JudgeCandidate(without, job.validation, residual_tau, samples, b_without, r->implausibility,
                               std::max(1, added),
                               spec.kind == EffectKind::kSpring    ? PriorOdds::kRare
                               : spec.kind == EffectKind::kPayload ? PriorOdds::kOrdinary
                                                                   : PriorOdds::kCommon,
                               rules);
  r->explained = r->evidence.explained;
}

// The result of candidate `c` fitted on its own (`job`), judged against the model.
CandidateResult CandidateResultOf(const CandidateList& list, size_t c, const Job& job, const JointDiagnosis& out,
                                  const JointDiagnosisOptions& options) {
  const EffectSpec& spec = list.specs[c];
  CandidateResult r;
  r.spec = spec;
  r.name = spec.text;
  (spec.kind == EffectKind::kPayload ? r.link : r.joint) = spec.target;
  if (list.replaces[c]) r.replaces = EffectItem(*list.replaces[c]);
  JudgeJob(job, spec, list.replaces[c], out.fit_validation, out.implausibility, out.residual_tau,
           out.validation_samples, options, &r);
  r.converged = job.fit.lm.converged();
  r.iterations = job.fit.lm.iterations;
  if (spec.kind == EffectKind::kPayload) {
    const int e = static_cast<int>(job.model->bodies().size()) - 1;  // the payload: the last body
    const Vector10 pi = job.model->BodyInertia(e, job.fit.x).vector();
    r.values.assign(pi.data(), pi.data() + 10);
    if (e < static_cast<int>(job.stds.size())) r.payload_std = job.stds[e];
  } else {
    // The candidate's term: the one of its kind on its joint.
    for (int k = 0; k < static_cast<int>(job.model->effects().size()); ++k) {
      const EffectTerm& t = job.model->effects()[k];
      if (t.kind == spec.kind && t.joint == spec.target) r.values = job.model->EffectValues(k, job.fit.x);
    }
  }
  return r;
}

// Ranked as candidate_ranking.hpp says. Alternatives to the top suggestion: each further
// suggestion refitted together with the top one must still be supported against the top one
// alone; two dry-friction forms of one joint are alternatives by construction (one slot per joint).
void RankJointCandidates(const Fitter& fitter, const std::vector<EffectSpec>& effects,
                         const std::vector<std::string>& joints, const CandidateList& list,
                         const std::vector<Job>& jobs, JointDiagnosis* out) {
  const JointDiagnosisOptions& options = fitter.options;
  std::vector<CandidateResult>& candidates = out->candidates;
  const SameAsTopTest same_as_top = [&](int top, const std::vector<int>& others) {
    std::vector<bool> same(others.size(), false);
    const EffectSpec& top_spec = candidates[top].spec;
    const std::vector<EffectSpec> with_top = WithCandidate(effects, joints, top_spec, list.replaces[top]);
    std::vector<size_t> refit;  // into others
    for (size_t k = 0; k < others.size(); ++k) {
      const EffectSpec& o = candidates[others[k]].spec;
      if (IsDryFriction(o.kind) && IsDryFriction(top_spec.kind) && o.target == top_spec.target) {
        same[k] = true;
      } else {
        refit.push_back(k);
      }
    }
    const std::unordered_map<std::string, double> top_x = NamedParameters(*jobs[top].model, jobs[top].fit.x);
    std::vector<Job> pairs(refit.size());
    for (size_t k = 0; k < refit.size(); ++k) {
      const int other = others[refit[k]];
      fitter.SetupWarm(pairs[k], WithCandidate(with_top, joints, candidates[other].spec, list.replaces[other]), top_x);
    }
    fitter.Run(pairs, options.threads);
    for (size_t k = 0; k < refit.size(); ++k) {
      const int other = others[refit[k]];
      CandidateResult together;
      JudgeJob(pairs[k], candidates[other].spec, list.replaces[other], candidates[top].validation,
               candidates[top].implausibility, out->residual_tau, out->validation_samples, options, &together);
      same[refit[k]] = !together.evidence.suggested();
    }
    return same;
  };
  std::vector<CandidateEvidence> evidence;
  for (const CandidateResult& r : candidates) evidence.push_back(r.evidence);
  RankingOptions ranking;
  ranking.same_as_top = same_as_top;
  ranking.model_converged = out->fit.lm.converged();
  const CandidateRanking ranked = RankCandidates(evidence, ranking);
  for (size_t i = 0; i < candidates.size(); ++i) {
    if (ranked.alternative_to[i] >= 0) candidates[i].alternative_to = candidates[ranked.alternative_to[i]].name;
  }
  std::vector<CandidateResult> sorted;
  for (int i : ranked.order) sorted.push_back(std::move(candidates[i]));
  candidates = std::move(sorted);
  out->num_suggestions = ranked.num_suggestions;
  if (!out->fit.lm.converged()) {
    out->notes.push_back("the model's own fit did not converge (" + std::string(ToString(out->fit.lm.reason)) +
                         " after " + std::to_string(out->fit.lm.iterations) +
                         " iterations): its candidates would all look good, so none is suggested; raise the "
                         "iteration cap");
  }
}

JointDiagnosis Diagnose(const RobotModelFactory& make, const std::vector<EffectSpec>& effects,
                        const std::vector<std::string>& payload_links, const JointSamples& train,
                        const JointSamples& validation, const JointDiagnosisOptions& options, Prepared* prepared) {
  const auto start = std::chrono::steady_clock::now();
  JointDiagnosis out;
  out.effects = effects;
  if (!(options.prior_tolerance > 0.0) || !std::isfinite(options.prior_tolerance)) {
    throw std::invalid_argument("diagnosis: the prior tolerance must be a positive number, not " +
                                std::to_string(options.prior_tolerance));
  }
  out.prior_tolerance = options.prior_tolerance;
  const RobotDynamics base = make(effects);
  if (base.num_dofs() == 0) throw std::invalid_argument("diagnosis: the robot has no moving joint");
  if (static_cast<long>(train.size()) * base.num_dofs() < base.num_parameters()) {
    throw std::invalid_argument("diagnosis: " + std::to_string(train.size()) + " training samples give " +
                                std::to_string(static_cast<long>(train.size()) * base.num_dofs()) +
                                " torque equations, fewer than the model's " + std::to_string(base.num_parameters()) +
                                " parameters");
  }
  Prepared local;
  Prepared& data = prepared != nullptr ? *prepared : local;
  if (!data.shapes_fitted) FitFrictionShapes(make, effects, options.joint_kinds, train, &data);
  CandidateList list = ListCandidates(base, effects, payload_links, options, data);
  CheckDetermined(base, list, train.size(), options);
  // One model with every joint candidate: its features hold every model's features.
  std::vector<EffectSpec> catalog_effects = effects;
  for (const EffectSpec& s : list.specs) {
    if (s.kind != EffectKind::kPayload) catalog_effects.push_back(s);
  }
  const int threads = options.threads > 0 ? options.threads
                                          : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  if (!data.catalog) PrepareStatistics(make, catalog_effects, train, validation, threads, &data);
  out.train_samples = train.size();
  out.validation_samples = validation.size();
  const Fitter fitter{make, options, data};
  FitTheModel(fitter, base, effects, threads, &out);
  // Payload candidates come after the model's fit (with free links, only on links it bends).
  AddBentLinkPayloads(base, payload_links, options, out, &list);

  // Each candidate on its own, warm-started from the model's fit.
  const std::unordered_map<std::string, double> base_x = NamedParameters(base, out.fit.x);
  std::vector<Job> jobs(list.specs.size());
  for (size_t c = 0; c < list.specs.size(); ++c) {
    fitter.SetupWarm(jobs[c], WithCandidate(effects, base.dof_names(), list.specs[c], list.replaces[c]), base_x);
  }
  fitter.Run(jobs, options.threads);
  for (size_t c = 0; c < list.specs.size(); ++c) out.candidates.push_back(CandidateResultOf(list, c, jobs[c], out, options));
  RankJointCandidates(fitter, effects, base.dof_names(), list, jobs, &out);
  out.held_out = CompareJointModel(base, out.fit.x, validation);
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

}  // namespace

std::vector<EffectSpec> EffectsWithCandidate(const std::vector<EffectSpec>& effects,
                                             const std::vector<std::string>& joints, const CandidateResult& candidate) {
  std::optional<EffectSpec> replaced;
  if (!candidate.replaces.empty()) replaced = ParseEffectList(candidate.replaces).at(0);
  return WithCandidate(effects, joints, candidate.spec, replaced);
}

JointDiagnosis DiagnoseJointModel(const RobotModelFactory& make, const std::vector<EffectSpec>& effects,
                                  const std::vector<std::string>& payload_links, const JointSamples& train,
                                  const JointSamples& validation, const JointDiagnosisOptions& options) {
  return Diagnose(make, effects, payload_links, train, validation, options, nullptr);
}

JointDiagnosis IterateJointDiagnosis(const RobotModelFactory& make, const std::vector<EffectSpec>& effects,
                                     const std::vector<std::string>& payload_links, const JointSamples& train,
                                     const JointSamples& validation, const JointDiagnosisOptions& options,
                                     int max_steps, std::vector<DiagnosisStep>* steps) {
  const auto start = std::chrono::steady_clock::now();
  std::vector<EffectSpec> current = effects;
  Prepared prepared;  // the first step's statistics serve every step
  JointDiagnosis d = Diagnose(make, current, payload_links, train, validation, options, &prepared);
  steps->clear();
  for (int step = 0; step < max_steps && d.num_suggestions > 0; ++step) {
    if (options.progress) options.progress(step + 1, max_steps);
    const CandidateResult& top = d.candidates[0];
    DiagnosisStep s;
    s.added = top.name;
    s.item = EffectItem(top.spec);
    s.explained = top.explained;
    s.evidence = top.evidence;
    s.before = d.fit_validation;
    s.implausibility_before = d.implausibility;
    s.bent_before = BentLinks(d);
    s.replaced = top.replaces;
    current = EffectsWithCandidate(current, make({}).dof_names(), top);
    d = Diagnose(make, current, payload_links, train, validation, options, &prepared);
    s.after = d.fit_validation;
    s.implausibility_after = d.implausibility;
    s.bent_after = BentLinks(d);
    steps->push_back(s);
  }
  if (!d.fit.lm.converged()) {
    d.stop_reason = "the model's own fit did not converge";
  } else if (d.num_suggestions == 0) {
    d.stop_reason = "nothing more is suggested: no candidate is supported by the held-out data or by the links' plausibility";
  } else {
    d.stop_reason = "the step cap (" + std::to_string(max_steps) + ") was reached with " + d.candidates[0].name +
                    " still suggested";
  }
  // links_only_validation is relative to the links, whatever was added.
  d.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return d;
}

std::vector<std::string> BentLinks(const JointDiagnosis& d) {
  std::vector<std::string> bent;
  for (size_t e = 0; e < d.plausibility.size() && e < d.links.size() && e < d.body_names.size(); ++e) {
    if (d.links[e] && !d.plausibility[e].Within(d.prior_tolerance)) bent.push_back(d.body_names[e]);
  }
  return bent;
}

void SplitHoldout(const JointSamples& data, double fraction, JointSamples* train, JointSamples* validation) {
  const int N = data.size();
  const int held = N - HoldoutStart(data.t, fraction);
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
