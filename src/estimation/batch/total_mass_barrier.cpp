#include "inertial/estimation/batch/total_mass_barrier.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "inertial/estimation/batch/region_barrier.hpp"

namespace inertial {
namespace {

void CheckBound(const RobotDynamics& model, const TotalMassBound& bound, const Eigen::VectorXd& x) {
  if (!(bound.total > 0.0) || !std::isfinite(bound.total)) {
    throw std::invalid_argument("total mass: the bound must be a positive finite mass (" + std::to_string(bound.total) +
                                " kg given)");
  }
  if (!(bound.fixed >= 0.0) || !std::isfinite(bound.fixed)) {
    throw std::invalid_argument("total mass: the mass fixed to the base must be finite and non-negative");
  }
  if (x.size() != model.num_parameters()) {
    throw std::invalid_argument("total mass: " + std::to_string(x.size()) + " parameters, the model has " +
                                std::to_string(model.num_parameters()));
  }
}

// m_e = e^{2 alpha_e} m_prior,e (file comment).
double LinkMass(const RobotDynamics& model, const Eigen::VectorXd& x, int e) {
  return std::exp(2.0 * x[10 * e]) * model.bodies()[static_cast<size_t>(e)].prior.mass();
}

}  // namespace

bool IsRobotLink(const RobotDynamics& model, int e) {
  return e >= 0 && e < model.tree().num_bodies() && !model.tree().is_rotor(e);
}

double LinkMassSum(const RobotDynamics& model, const Eigen::VectorXd& x) {
  double sum = 0.0;
  for (int e = 0; e < static_cast<int>(model.bodies().size()); ++e) {
    if (IsRobotLink(model, e)) sum += LinkMass(model, x, e);
  }
  return sum;
}

double TotalMassBarrier(const RobotDynamics& model, const TotalMassBound& bound, const Eigen::VectorXd& x, bool newton,
                        Eigen::VectorXd* g, Eigen::MatrixXd* H) {
  CheckBound(model, bound, x);
  const double M = bound.total;
  const double r = 1.0 - (bound.fixed + LinkMassSum(model, x)) / M;
  const OneSidedLog phi = OneSidedLogBarrier(r, kTotalMassOnset);
  if (!std::isfinite(phi.value)) return std::numeric_limits<double>::infinity();
  const int P = model.num_parameters();
  if (g != nullptr) g->setZero(P);
  if (H != nullptr) H->setZero(P, P);
  if (phi.value == 0.0 && phi.first == 0.0) return 0.0;  // at or below the onset: nothing at all
  for (int e = 0; e < static_cast<int>(model.bodies().size()); ++e) {
    if (!IsRobotLink(model, e)) continue;
    const double dr_e = -2.0 * LinkMass(model, x, e) / M;
    if (g != nullptr) (*g)[10 * e] = phi.first * dr_e;
    if (H == nullptr) continue;
    for (int f = 0; f < static_cast<int>(model.bodies().size()); ++f) {
      if (IsRobotLink(model, f)) (*H)(10 * e, 10 * f) = phi.second * dr_e * (-2.0 * LinkMass(model, x, f) / M);
    }
    if (newton) (*H)(10 * e, 10 * e) += phi.first * 2.0 * dr_e;  // phi'(r) d2r/dalpha_e2, d2r = 2 dr_e
  }
  return phi.value;
}

double AddTotalMassBarrier(const RobotDynamics& model, const TotalMassBound& bound, const Eigen::VectorXd& x, double mu,
                           bool newton, const std::vector<bool>& frozen_bodies, Eigen::VectorXd* g, Eigen::MatrixXd* H) {
  const bool derivatives = g != nullptr && H != nullptr;
  Eigen::VectorXd g_b;
  Eigen::MatrixXd H_b;
  const double b = TotalMassBarrier(model, bound, x, newton, derivatives ? &g_b : nullptr, derivatives ? &H_b : nullptr);
  if (!std::isfinite(b) || !derivatives || b == 0.0) return b;
  const auto frozen = [&](int e) { return !frozen_bodies.empty() && frozen_bodies[static_cast<size_t>(e)]; };
  for (int e = 0; e < static_cast<int>(model.bodies().size()); ++e) {
    if (!IsRobotLink(model, e) || frozen(e)) continue;
    (*g)[10 * e] += 0.5 * mu * g_b[10 * e];
    for (int f = 0; f < static_cast<int>(model.bodies().size()); ++f) {
      if (IsRobotLink(model, f) && !frozen(f)) (*H)(10 * e, 10 * f) += 0.5 * mu * H_b(10 * e, 10 * f);
    }
  }
  return b;
}

Eigen::VectorXd IntoTotalMassBound(const RobotDynamics& model, const TotalMassBound& bound, const Eigen::VectorXd& x,
                                   const std::vector<bool>& movable) {
  CheckBound(model, bound, x);
  const double M = bound.total;
  double moving = 0.0, held = bound.fixed;
  const auto may_move = [&](int e) { return movable.empty() || movable[static_cast<size_t>(e)]; };
  for (int e = 0; e < static_cast<int>(model.bodies().size()); ++e) {
    if (!IsRobotLink(model, e)) continue;
    (may_move(e) ? moving : held) += LinkMass(model, x, e);
  }
  if (moving + held < M) return x;
  const double target = (1.0 - kTotalMassOnset) * M - held;
  if (!(target > 0.0) || !(moving > 0.0)) {
    throw std::invalid_argument("total mass: the links whose mass the fit holds and those fixed to the base weigh " +
                                std::to_string(held) + " kg, which leaves no room under the bound of " +
                                std::to_string(M) + " kg for the " + std::to_string(moving) + " kg of the others");
  }
  Eigen::VectorXd out = x;
  const double shift = 0.5 * std::log(target / moving);  // m -> m e^{2 shift}
  for (int e = 0; e < static_cast<int>(model.bodies().size()); ++e) {
    if (IsRobotLink(model, e) && may_move(e)) out[10 * e] += shift;
  }
  return out;
}

}  // namespace inertial
