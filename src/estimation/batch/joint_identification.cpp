#include "inertial/estimation/batch/joint_identification.hpp"
#include "inertial/estimation/batch/region_barrier.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "inertial/inertia/log_det_divergence.hpp"

namespace inertial {
namespace {

void CheckSamples(const RobotDynamics& model, const JointSamples& data) {
  const int n = model.num_dofs();
  if (data.joint_names != model.dof_names()) {
    throw std::invalid_argument("identification: the samples' joints are not the model's DOFs in order");
  }
  const int N = data.size();
  if (data.q.rows() != N || data.qd.rows() != N || data.qdd.rows() != N || data.tau.rows() != N ||
      data.q.cols() != n || data.qd.cols() != n || data.qdd.cols() != n || data.tau.cols() != n) {
    throw std::invalid_argument("identification: sample arrays must be " + std::to_string(N) + " x " +
                                std::to_string(n));
  }
}

}  // namespace

JointNormalEquations AccumulateNormalEquations(const RobotDynamics& model, const JointSamples& data) {
  CheckSamples(model, data);
  const int n = model.num_dofs(), F = model.num_features(), N = data.size();
  constexpr int kChunk = 64;  // samples per block update of A^T A
  JointNormalEquations eq;
  eq.AtA = Eigen::MatrixXd::Zero(F, F);
  eq.Atb = Eigen::VectorXd::Zero(F);
  eq.num_samples = N;
  Eigen::MatrixXd A(kChunk * n, F);
  Eigen::VectorXd b(kChunk * n);
  for (int start = 0; start < N; start += kChunk) {
    const int count = std::min(kChunk, N - start);
    for (int s = 0; s < count; ++s) {
      const int j = start + s;
      model.Features(data.q.row(j).transpose(), data.qd.row(j).transpose(), data.qdd.row(j).transpose(),
                     A.middleRows(s * n, n));
      b.segment(s * n, n) = data.tau.row(j).transpose();
    }
    const auto rows = A.topRows(count * n);
    eq.AtA.selfadjointView<Eigen::Lower>().rankUpdate(rows.transpose());
    eq.Atb.noalias() += rows.transpose() * b.head(count * n);
    eq.btb += b.head(count * n).squaredNorm();
  }
  eq.AtA.triangularView<Eigen::StrictlyUpper>() = eq.AtA.transpose();
  return eq;
}

std::vector<JointNormalEquations> AccumulateJointwiseNormalEquations(const RobotDynamics& model,
                                                                     const JointSamples& data) {
  CheckSamples(model, data);
  const int n = model.num_dofs(), F = model.num_features(), N = data.size();
  constexpr int kChunk = 64;  // samples per block update
  std::vector<JointNormalEquations> eqs(n);
  for (JointNormalEquations& eq : eqs) {
    eq.AtA = Eigen::MatrixXd::Zero(F, F);
    eq.Atb = Eigen::VectorXd::Zero(F);
    eq.num_samples = N;
  }
  Eigen::MatrixXd A(n, F);
  std::vector<Eigen::MatrixXd> rows(n, Eigen::MatrixXd(kChunk, F));
  Eigen::MatrixXd b(kChunk, n);
  for (int start = 0; start < N; start += kChunk) {
    const int count = std::min(kChunk, N - start);
    for (int s = 0; s < count; ++s) {
      const int j = start + s;
      model.Features(data.q.row(j).transpose(), data.qd.row(j).transpose(), data.qdd.row(j).transpose(), A);
      for (int k = 0; k < n; ++k) rows[k].row(s) = A.row(k);
      b.row(s) = data.tau.row(j);
    }
    for (int k = 0; k < n; ++k) {
      const auto block = rows[k].topRows(count);
      eqs[k].AtA.selfadjointView<Eigen::Lower>().rankUpdate(block.transpose());
      eqs[k].Atb.noalias() += block.transpose() * b.col(k).head(count);
      eqs[k].btb += b.col(k).head(count).squaredNorm();
    }
  }
  for (JointNormalEquations& eq : eqs) eq.AtA.triangularView<Eigen::StrictlyUpper>() = eq.AtA.transpose();
  return eqs;
}

double SquaredError(const JointNormalEquations& eq, const Eigen::VectorXd& w) {
  const double e = w.dot(eq.AtA * w) - 2.0 * w.dot(eq.Atb) + eq.btb;
  return e < 0.0 ? 0.0 : e;  // rounding can make it slightly negative; NaN stays NaN
}

Eigen::VectorXd DefaultInitialParameters(const RobotDynamics& model, const JointNormalEquations& data,
                                         const std::vector<bool>& frozen_bodies) {
  const int F = model.num_features(), P = model.num_parameters(), Fi = model.num_inertia_features();
  if (data.AtA.rows() != F || data.AtA.cols() != F || data.Atb.size() != F) {
    throw std::invalid_argument("identification: normal equations do not match the model's features");
  }
  // Effects from the unconstrained linear least-squares fit of the whole model (bodies' pi free
  // too, so that the priors' errors do not leak into the effects; a tree body whose every estimated
  // body is frozen keeps the prior's pi), every non-negative coefficient at least 1e-3 of its
  // feature's natural scale sqrt(b^T b / (A_k^T A_k)) (the coefficient at which that feature alone
  // would explain the whole torque RMS): a coefficient started at ~0 would sit on a plateau of
  // e^s, whose gradient vanishes there.
  Eigen::VectorXd x0 = Eigen::VectorXd::Zero(P);
  const int Fe = F - Fi;
  if (Fe == 0) return x0;
  const int T = Fi / 10;
  std::vector<int> estimated(T, 0), thawed(T, 0);
  for (int e = 0; e < static_cast<int>(model.bodies().size()); ++e) {
    const int b = model.bodies()[e].block;
    ++estimated[b];
    if (frozen_bodies.empty() || !frozen_bodies[e]) ++thawed[b];
  }
  std::vector<int> free_features;
  for (int b = 0; b < T; ++b) {
    if (estimated[b] == 0 || thawed[b] > 0) {
      for (int i = 0; i < 10; ++i) free_features.push_back(10 * b + i);
    }
  }
  for (int f = Fi; f < F; ++f) free_features.push_back(f);
  const Eigen::VectorXd w_prior = model.Coefficients(Eigen::VectorXd::Zero(P));
  Eigen::VectorXd w_fixed = w_prior;
  for (int f : free_features) w_fixed[f] = 0.0;
  const Eigen::VectorXd rhs_all = data.Atb - data.AtA * w_fixed;
  const int n = static_cast<int>(free_features.size());
  Eigen::MatrixXd M(n, n);
  Eigen::VectorXd rhs(n);
  for (int i = 0; i < n; ++i) {
    rhs[i] = rhs_all[free_features[i]];
    for (int j = 0; j < n; ++j) M(i, j) = data.AtA(free_features[i], free_features[j]);
  }
  M.diagonal().array() += 1e-10 * (M.diagonal().maxCoeff() + 1e-300);
  Eigen::VectorXd c = M.ldlt().solve(rhs).tail(Fe);
  if (!c.allFinite()) c.setZero();
  for (const EffectTerm& t : model.effects()) {
    if (t.kind == EffectKind::kOffset) continue;
    const int k = t.first_feature - Fi;
    const int non_negative = t.kind == EffectKind::kSpring ? 1 : t.size();  // a spring's k q0 is free
    for (int i = 0; i < non_negative; ++i) {
      const double natural =
          std::sqrt(data.btb / std::max(data.AtA(t.first_feature + i, t.first_feature + i), 1e-300));
      c[k + i] = std::max(c[k + i], 1e-3 * natural);
    }
    if (t.kind == EffectKind::kSpring) c[k + 1] = std::clamp(c[k + 1], -1e3 * c[k], 1e3 * c[k]);  // |q0| <= 1e3
  }
  return model.ParametersFromEffectCoefficients(c, 1e-300);
}

Eigen::VectorXd PriorParametersWithoutEffects(const RobotDynamics& model) {
  Eigen::VectorXd x = Eigen::VectorXd::Zero(model.num_parameters());
  for (const EffectTerm& t : model.effects()) {
    if (t.kind == EffectKind::kOffset) continue;
    x[t.first_parameter] = std::log(1e-300);
    if (t.kind == EffectKind::kAsymmetric) x[t.first_parameter + 1] = std::log(1e-300);
  }
  return x;
}

namespace {

// Whether estimated body e is frozen (held at its prior) by the flags (empty: none is).
bool IsFrozen(const std::vector<bool>& frozen_bodies, int e) { return !frozen_bodies.empty() && frozen_bodies[e]; }

// Rejects normal equations that do not match the model, and invalid options, in that order.
void CheckIdentificationInputs(const RobotDynamics& model, const JointNormalEquations& data,
                               const JointIdentificationOptions& options) {
  const int F = model.num_features(), P = model.num_parameters();
  if (data.AtA.rows() != F || data.AtA.cols() != F || data.Atb.size() != F) {
    throw std::invalid_argument("identification: normal equations do not match the model's features");
  }
  if (!(options.prior_weight >= 0.0) || !std::isfinite(options.prior_weight)) {
    throw std::invalid_argument("identification: the prior weight must be finite and non-negative");
  }
  const int B = static_cast<int>(model.bodies().size());
  if (!options.frozen_bodies.empty() && static_cast<int>(options.frozen_bodies.size()) != B) {
    throw std::invalid_argument("identification: frozen_bodies must have one flag per estimated body");
  }
  if (options.initial.size() != 0 && (options.initial.size() != P || !options.initial.allFinite())) {
    throw std::invalid_argument("identification: the initial parameters must be " + std::to_string(P) +
                                " finite numbers");
  }
  for (int p : options.held_parameters) {
    if (p < 0 || p >= P) throw std::invalid_argument("identification: a held parameter is not an entry of x");
  }
}

// One block of the coefficients' Jacobian J_w: rows [row, row + rows) (features), columns
// [col, col + cols) (parameters).
struct JacobianBlock {
  int row, col, rows, cols;
};

// J_w is block diagonal up to row placement (RobotDynamics::Coefficients): a 10 x 10 block per
// body at its tree body's features, a 1 x 1 (spring, asymmetric: 2 x 2) block per effect term.
std::vector<JacobianBlock> CoefficientJacobianBlocks(const RobotDynamics& model) {
  std::vector<JacobianBlock> blocks;
  const int B = static_cast<int>(model.bodies().size());
  for (int e = 0; e < B; ++e) blocks.push_back({10 * model.bodies()[e].block, 10 * e, 10, 10});
  for (const EffectTerm& t : model.effects()) blocks.push_back({t.first_feature, t.first_parameter, t.size(), t.size()});
  return blocks;
}

// The Gauss-Newton Hessian H = J_w^T A^T A J_w, block by block: 4 F P * 10 flops instead of the
// dense product's 2 F P (F + P). AtA_J is workspace.
void GaussNewtonHessian(const Eigen::MatrixXd& AtA, const Eigen::MatrixXd& J_w, const std::vector<JacobianBlock>& blocks,
                        int F, int P, Eigen::MatrixXd& AtA_J, Eigen::MatrixXd* H) {
  AtA_J.resize(F, P);
  for (const JacobianBlock& b : blocks) {
    AtA_J.middleCols(b.col, b.cols).noalias() = AtA.middleCols(b.row, b.rows) * J_w.block(b.row, b.col, b.rows, b.cols);
  }
  H->resize(P, P);
  for (const JacobianBlock& b : blocks) {
    H->middleRows(b.col, b.cols).noalias() =
        J_w.block(b.row, b.col, b.rows, b.cols).transpose() * AtA_J.middleRows(b.row, b.rows);
  }
}

// Adds the second-order term sum_k grad_w[k] d2 w_k / dx2 that Gauss-Newton drops. Without it, the
// fit crawls along the curved valleys that unexcited directions of w make in theta (steep data
// walls, a floor held only by the regularizer).
void AddSecondOrderTerms(const RobotDynamics& model, const Eigen::VectorXd& x, const Eigen::VectorXd& w,
                         const Eigen::VectorXd& grad_w, Eigen::MatrixXd* H) {
  const int B = static_cast<int>(model.bodies().size());
  for (int e = 0; e < B; ++e) {
    const EstimatedBody& body = model.bodies()[e];
    H->block<10, 10>(10 * e, 10 * e) +=
        body.map.ContractedHessian(x.segment<10>(10 * e), grad_w.segment<10>(10 * body.block));
  }
  for (const EffectTerm& t : model.effects()) {
    const int p = t.first_parameter, f = t.first_feature;
    if (t.kind == EffectKind::kOffset) continue;
    (*H)(p, p) += grad_w[f] * w[f];  // w = e^s: d2w/ds2 = w
    if (t.kind == EffectKind::kAsymmetric) (*H)(p + 1, p + 1) += grad_w[f + 1] * w[f + 1];
    if (t.kind == EffectKind::kSpring) {  // w[f + 1] = e^s q0
      (*H)(p, p) += grad_w[f + 1] * w[f + 1];
      (*H)(p, p + 1) += grad_w[f + 1] * w[f];
      (*H)(p + 1, p) += grad_w[f + 1] * w[f];
    }
  }
}

}  // namespace

void HoldParameters(const JointIdentificationOptions& options, Eigen::VectorXd* g, Eigen::MatrixXd* H) {
  auto hold = [&](int first, int count) {
    g->segment(first, count).setZero();
    H->middleRows(first, count).setZero();
    H->middleCols(first, count).setZero();
    H->block(first, first, count, count).setIdentity();
  };
  for (size_t e = 0; e < options.frozen_bodies.size(); ++e) {
    if (options.frozen_bodies[e]) hold(10 * static_cast<int>(e), 10);
  }
  for (int p : options.held_parameters) hold(p, 1);
}

JointIdentificationResult IdentifyJointModel(const RobotDynamics& model, const JointNormalEquations& data,
                                             const JointIdentificationOptions& options) {
  CheckIdentificationInputs(model, data, options);
  const int F = model.num_features(), P = model.num_parameters();
  JointIdentificationResult result;
  const int B = static_cast<int>(model.bodies().size());
  Eigen::VectorXd x0 =
      options.initial.size() != 0 ? options.initial : DefaultInitialParameters(model, data, options.frozen_bodies);
  for (int e = 0; e < B; ++e) {
    // A frozen body sits at its prior; so does one whose given start lies outside its region (a
    // warm start from a model without regions), since every iterate must be inside.
    if (IsFrozen(options.frozen_bodies, e) ||
        (model.bodies()[e].region && !std::isfinite(RegionBarrier(model.bodies()[e], x0.segment<10>(10 * e), false)))) {
      x0.segment<10>(10 * e).setZero();
    }
  }
  if (options.total_mass) {  // a start beyond the weighed mass: the links that may move scaled down
    std::vector<bool> movable(static_cast<size_t>(B), true);
    for (int e = 0; e < B; ++e) movable[static_cast<size_t>(e)] = !IsFrozen(options.frozen_bodies, e);
    for (int p : options.held_parameters) {
      if (p < 10 * B && p % 10 == 0) movable[static_cast<size_t>(p / 10)] = false;  // a held alpha: a held mass
    }
    x0 = IntoTotalMassBound(model, *options.total_mass, x0, movable);
  }
  result.x_initial = x0;

  const double gamma = options.prior_weight;
  Eigen::MatrixXd J_w, AtA_J;
  const std::vector<JacobianBlock> blocks = CoefficientJacobianBlocks(model);
  Matrix10 J_r;
  const double mu = RegionBarrierWeight(data.btb, data.num_samples);
  // F(x) = 0.5 (||A w - tau||^2 + gamma sum d_b + mu sum b_b): data through A^T A only.
  auto problem = [&](const Eigen::VectorXd& x, double* cost, Eigen::VectorXd* g, Eigen::MatrixXd* H) {
    const bool derivatives = g != nullptr && H != nullptr;
    const Eigen::VectorXd w = model.Coefficients(x, derivatives ? &J_w : nullptr);
    const Eigen::VectorXd Hw = data.AtA * w;
    const double data_sq = std::max(0.0, w.dot(Hw) - 2.0 * w.dot(data.Atb) + data.btb);
    double reg = 0.0;
    if (derivatives) {
      const Eigen::VectorXd grad_w = Hw - data.Atb;
      *g = J_w.transpose() * grad_w;
      GaussNewtonHessian(data.AtA, J_w, blocks, F, P, AtA_J, H);
      if (options.newton) AddSecondOrderTerms(model, x, w, grad_w, H);
    }
    for (int e = 0; e < B; ++e) {
      const Vector10 r =
          LogDetDivergenceResiduals(model.bodies()[e].map, x.segment<10>(10 * e), derivatives ? &J_r : nullptr);
      reg += r.squaredNorm();
      if (derivatives) {
        g->segment<10>(10 * e) += gamma * J_r.transpose() * r;
        H->block<10, 10>(10 * e, 10 * e) += gamma * J_r.transpose() * J_r;
      }
    }
    // Every body inside its region (region_barrier.hpp); outside, Levenberg-Marquardt rejects the step.
    double barrier = AddRegionBarriers(model, x, mu, options.newton, options.frozen_bodies, g, H);
    // The links' masses within the robot's weighed total (total_mass_barrier.hpp), with the same weight.
    if (options.total_mass && std::isfinite(barrier)) {
      barrier += AddTotalMassBarrier(model, *options.total_mass, x, mu, options.newton, options.frozen_bodies, g, H);
    }
    if (!std::isfinite(barrier)) return false;
    if (derivatives) HoldParameters(options, g, H);
    *cost = 0.5 * (data_sq + gamma * reg + mu * barrier);
    return std::isfinite(*cost);
  };
  result.lm = MinimizeLevenbergMarquardt(problem, x0, options.lm);
  result.x = result.lm.x;
  result.data_cost = SquaredError(data, model.Coefficients(result.x));
  for (int e = 0; e < B; ++e) {
    result.regularizer += LogDetDivergenceResiduals(model.bodies()[e].map, result.x.segment<10>(10 * e)).squaredNorm();
  }
  return result;
}

Eigen::MatrixXd PredictJointTorques(const RobotDynamics& model, const Eigen::VectorXd& x, const JointSamples& data) {
  CheckSamples(model, data);
  const Eigen::VectorXd w = model.Coefficients(x);
  Eigen::MatrixXd tau(data.size(), model.num_dofs());
  Eigen::MatrixXd A(model.num_dofs(), model.num_features());
  for (int j = 0; j < data.size(); ++j) {
    model.Features(data.q.row(j).transpose(), data.qd.row(j).transpose(), data.qdd.row(j).transpose(), A);
    tau.row(j) = (A * w).transpose();
  }
  return tau;
}

TorqueErrors CompareTorques(const Eigen::MatrixXd& predicted, const Eigen::MatrixXd& measured) {
  if (predicted.rows() != measured.rows() || predicted.cols() != measured.cols() || measured.rows() == 0) {
    throw std::invalid_argument("torque comparison: predicted and measured must have the same non-empty shape");
  }
  TorqueErrors e;
  const double N = static_cast<double>(measured.rows());
  const Eigen::MatrixXd err = predicted - measured;
  e.rms = (err.colwise().squaredNorm() / N).cwiseSqrt().transpose();
  const Eigen::VectorXd scale = (measured.colwise().squaredNorm() / N).cwiseSqrt().transpose();
  e.relative_rms = e.rms.cwiseQuotient(scale.cwiseMax(1e-300));
  e.total_rms = std::sqrt(err.squaredNorm() / err.size());
  e.total_relative_rms = std::sqrt(err.squaredNorm() / std::max(measured.squaredNorm(), 1e-300));
  return e;
}

}  // namespace inertial
