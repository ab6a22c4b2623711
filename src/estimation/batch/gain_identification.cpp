#include "inertial/estimation/batch/gain_identification.hpp"
#include "inertial/estimation/batch/region_barrier.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "inertial/inertia/log_det_divergence.hpp"


namespace inertial {
namespace {

// The samples with their tau replaced by `columns` (rows = samples).
JointSamples WithTorques(const JointSamples& data, const Eigen::MatrixXd& columns) {
  JointSamples out = data;
  out.tau = columns;
  return out;
}

// Levenberg-Marquardt over z = [x; log g] of the log-space cost (IdentifyWithGains), from x0, g0.
DenseLevenbergMarquardtResult FitInLogSpace(const RobotDynamics& model, const GainProblem& p, const Eigen::VectorXd& x0,
                                            const Eigen::VectorXd& g0, const JointIdentificationOptions& options) {
  const int P = model.num_parameters(), G = static_cast<int>(p.dofs.size()), n = model.num_dofs();
  const int B = static_cast<int>(model.bodies().size());
  std::vector<int> slot(static_cast<size_t>(n), -1);  // DOF -> index among the gains
  for (int g = 0; g < G; ++g) slot[static_cast<size_t>(p.dofs[static_cast<size_t>(g)])] = g;
  Eigen::MatrixXd J_w;
  Matrix10 J_r;
  const JointNormalEquations eliminated = p.Eliminated();
  const double mu = RegionBarrierWeight(eliminated.btb, eliminated.num_samples);
  auto problem = [&](const Eigen::VectorXd& z, double* cost, Eigen::VectorXd* grad, Eigen::MatrixXd* H) {
    const bool derivatives = grad != nullptr && H != nullptr;
    const Eigen::VectorXd x = z.head(P);
    const Eigen::VectorXd w = model.Coefficients(x, derivatives ? &J_w : nullptr);
    double data = 0.0;
    Eigen::VectorXd gw = Eigen::VectorXd::Zero(w.size());
    Eigen::MatrixXd Hw = Eigen::MatrixXd::Zero(w.size(), w.size());
    if (derivatives) {
      grad->setZero(P + G);
      H->setZero(P + G, P + G);
    }
    Eigen::MatrixXd Hws = Eigen::MatrixXd::Zero(w.size(), G);
    for (int j = 0; j < n; ++j) {
      const int g = slot[static_cast<size_t>(j)];
      const double gain = g >= 0 ? std::exp(z[P + g]) : 1.0, bar = g >= 0 ? g0[g] : 1.0;
      const JointNormalEquations& y = p.logged[static_cast<size_t>(j)];
      const JointNormalEquations& k = p.known[static_cast<size_t>(j)];
      const Eigen::VectorXd Gw_ap = y.AtA * w + k.Atb;  // A^T (A w + p)
      const double mm = w.dot(y.AtA * w) + 2.0 * w.dot(k.Atb) + k.btb;  // ||A w + p||^2
      const double my = w.dot(y.Atb) + p.ytp[static_cast<size_t>(j)];  // y^T (A w + p)
      const double c = 1.0 / (bar * bar);
      data += c * (gain * gain * mm - 2.0 * gain * my + y.btb);
      if (!derivatives) continue;
      gw += c * (gain * gain * Gw_ap - gain * y.Atb);  // half the gradient of the data term in w
      Hw += c * gain * gain * y.AtA;
      if (g >= 0) {
        (*grad)[P + g] = c * (gain * gain * mm - gain * my);  // d/ds, s = log g (halved)
        Hws.col(g) = c * gain * gain * Gw_ap;
        (*H)(P + g, P + g) = c * gain * gain * mm;
      }
    }
    double reg = 0.0;
    if (derivatives) {
      grad->head(P) = J_w.transpose() * gw;
      H->topLeftCorner(P, P) = J_w.transpose() * Hw * J_w;
      H->topRightCorner(P, G) = J_w.transpose() * Hws;
      H->bottomLeftCorner(G, P) = H->topRightCorner(P, G).transpose();
    }
    for (int e = 0; e < B; ++e) {
      const Vector10 r = LogDetDivergenceResiduals(model.bodies()[static_cast<size_t>(e)].map, x.segment<10>(10 * e),
                                                   derivatives ? &J_r : nullptr);
      reg += r.squaredNorm();
      if (derivatives) {
        grad->segment<10>(10 * e) += options.prior_weight * J_r.transpose() * r;
        H->block<10, 10>(10 * e, 10 * e) += options.prior_weight * J_r.transpose() * J_r;
      }
    }
    // Every body inside its region, as in IdentifyJointModel (region_barrier.hpp).
    double barrier = AddRegionBarriers(model, x, mu, options.newton, options.frozen_bodies, grad, H);
    if (options.total_mass && std::isfinite(barrier)) {  // and within the robot's weighed mass
      barrier += AddTotalMassBarrier(model, *options.total_mass, x, mu, options.newton, options.frozen_bodies, grad, H);
    }
    if (!std::isfinite(barrier)) return false;
    if (derivatives) HoldParameters(options, grad, H);
    *cost = 0.5 * (std::max(data, 0.0) + options.prior_weight * reg + mu * barrier);
    return std::isfinite(*cost);
  };
  Eigen::VectorXd z0(P + G);
  z0.head(P) = x0;
  z0.tail(G) = g0.array().log().matrix();
  return MinimizeLevenbergMarquardt(problem, z0, options.lm);
}

}  // namespace

JointNormalEquations GainProblem::Eliminated() const {
  JointNormalEquations e = links;
  for (size_t g = 0; g < dofs.size(); ++g) {
    e.AtA -= Aty[g] * Aty[g].transpose() / yty[g];
    e.Atb -= Aty[g] * (ytb[g] / yty[g]);
    e.btb -= ytb[g] * ytb[g] / yty[g];
  }
  e.btb = std::max(e.btb, 0.0);
  return e;
}

Eigen::VectorXd GainProblem::InverseGains(const Eigen::VectorXd& w) const {
  Eigen::VectorXd h(static_cast<Eigen::Index>(dofs.size()));
  for (size_t g = 0; g < dofs.size(); ++g) h[static_cast<Eigen::Index>(g)] = (w.dot(Aty[g]) - ytb[g]) / yty[g];
  return h;
}

GainProblem AccumulateGainProblem(const RobotDynamics& model, const JointSamples& data, const Eigen::MatrixXd& known,
                                  const std::vector<int>& gain_dofs) {
  const int n = model.num_dofs(), N = data.size();
  if (known.size() != 0 && (known.rows() != N || known.cols() != n)) {
    throw std::invalid_argument("gains: the known torques must be " + std::to_string(N) + " x " + std::to_string(n));
  }
  if (data.tau.rows() != N || data.tau.cols() != n) {
    throw std::invalid_argument("gains: the samples must have " + std::to_string(n) + " torque columns");
  }
  GainProblem p;
  p.dofs = gain_dofs;
  for (size_t g = 0; g < gain_dofs.size(); ++g) {
    if (gain_dofs[g] < 0 || gain_dofs[g] >= n || (g > 0 && gain_dofs[g] <= gain_dofs[g - 1])) {
      throw std::invalid_argument("gains: the gain joints must be distinct DOFs in ascending order");
    }
  }
  const Eigen::MatrixXd k = known.size() != 0 ? known : Eigen::MatrixXd::Zero(N, n);
  Eigen::MatrixXd b = data.tau - k;  // what is known in N m; a gain joint's own log is not
  for (int d : gain_dofs) b.col(d) = -k.col(d);
  p.links = AccumulateNormalEquations(model, WithTorques(data, b));
  const std::vector<JointNormalEquations> logged = AccumulateJointwiseNormalEquations(model, data);
  p.logged = logged;
  p.known = AccumulateJointwiseNormalEquations(model, WithTorques(data, k));
  for (int d = 0; d < n; ++d) p.ytp.push_back(data.tau.col(d).dot(k.col(d)));
  for (int d : gain_dofs) {
    const JointNormalEquations& e = logged[static_cast<size_t>(d)];
    if (!(e.btb > 0.0)) {
      throw std::invalid_argument("gain@" + model.dof_names()[static_cast<size_t>(d)] +
                                  ": the joint's log is zero throughout, so it shows no torque to scale");
    }
    p.Aty.push_back(e.Atb);
    p.yty.push_back(e.btb);
    p.ytb.push_back(data.tau.col(d).dot(b.col(d)));
  }
  return p;
}

std::optional<std::string> GainScaleProblem(const RobotDynamics& model, const Eigen::MatrixXd& known,
                                            const std::vector<int>& gain_dofs, const std::vector<bool>& frozen_bodies,
                                            const std::vector<int>& held_parameters) {
  if (gain_dofs.empty() || static_cast<int>(gain_dofs.size()) < model.num_dofs()) return std::nullopt;
  for (int d : gain_dofs) {
    if (known.size() != 0 && known.col(d).cwiseAbs().maxCoeff() > 0.0) return std::nullopt;
  }
  for (bool frozen : frozen_bodies) {
    if (frozen) return std::nullopt;
  }
  const int body_parameters = 10 * static_cast<int>(model.bodies().size());
  for (int p : held_parameters) {
    if (p < body_parameters && p % 10 == 0) return std::nullopt;  // a body's alpha: a mass known in kg
  }
  return std::string("every joint's torque column is a logged quantity with an unknown gain, and nothing else is "
                     "known in N m, so the links and the gains could grow together without changing the fit: the "
                     "gains are not identifiable. Record a run carrying a payload of known mass "
                     "(--run-payload FILE=LINK:mass=M), or state one joint's gain (drop its gain@)");
}

GainIdentificationResult IdentifyWithGains(const RobotDynamics& model, const GainProblem& problem,
                                           const JointIdentificationOptions& options) {
  GainIdentificationResult r;
  r.fit = IdentifyJointModel(model, problem.Eliminated(), options);
  const Eigen::VectorXd w = model.Coefficients(r.fit.x);
  const Eigen::VectorXd h = problem.InverseGains(w);
  const int G = static_cast<int>(problem.dofs.size());
  for (int g = 0; g < G; ++g) {
    if (!(h[g] > 0.0) || !std::isfinite(h[g])) {
      throw std::invalid_argument("gain@" + model.dof_names()[static_cast<size_t>(problem.dofs[static_cast<size_t>(g)])] +
                                  ": the fitted gain is not positive (the log's sign is opposite to the torque's, or "
                                  "nothing in the log follows the model)");
    }
  }
  // From there, the fit in the log's space, where the noise is on the target (see the header).
  const DenseLevenbergMarquardtResult refined = FitInLogSpace(model, problem, r.fit.x, h.cwiseInverse(), options);
  r.fit.x = refined.x.head(model.num_parameters());
  r.fit.lm = refined;
  r.gains = refined.x.tail(G).array().exp().matrix();
  return r;
}

}  // namespace inertial
