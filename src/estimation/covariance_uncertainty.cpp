#include "inertial/estimation/covariance_uncertainty.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "inertial/estimation/fit_uncertainty.hpp"

namespace inertial {
namespace {

double Std(double variance) { return std::sqrt(std::max(0.0, variance)); }

// Effect term t's value stds from the coefficients' covariance (x = w).
std::vector<double> LinearEffectStds(const EffectTerm& t, const Eigen::VectorXd& w, const Eigen::MatrixXd& P) {
  const int f = t.first_feature;
  std::vector<double> stds{Std(P(f, f))};
  if (t.kind == EffectKind::kAsymmetric) stds.push_back(Std(P(f + 1, f + 1)));
  if (t.kind == EffectKind::kSpring) {  // q0 = w1 / w0
    const double k0 = w[f], kq = w[f + 1];
    const Eigen::Vector2d g(-kq / (k0 * k0), 1.0 / k0);
    stds.push_back(Std(g.dot(P.block<2, 2>(f, f) * g)));
  }
  return stds;
}

// Effect term k's value stds from the parameters' covariance (x of RobotDynamics).
std::vector<double> ParameterEffectStds(const RobotDynamics& model, int k, const Eigen::VectorXd& x,
                                        const Eigen::MatrixXd& P) {
  const EffectTerm& t = model.effects()[k];
  const int p = t.first_parameter;
  const std::vector<double> v = model.EffectValues(k, x);
  const double sd = Std(P(p, p));
  std::vector<double> stds{t.kind == EffectKind::kOffset ? sd : v[0] * sd};  // b = e^s: db = b ds
  if (t.kind == EffectKind::kSpring) stds.push_back(Std(P(p + 1, p + 1)));
  if (t.kind == EffectKind::kAsymmetric) stds.push_back(v[1] * Std(P(p + 1, p + 1)));
  return stds;
}

}  // namespace

CovarianceUncertainty UncertaintyFromCovariance(const RobotDynamics& model, const Eigen::VectorXd& x,
                                                const Eigen::MatrixXd& P, bool linear) {
  const int expected = linear ? model.num_features() : model.num_parameters();
  if (x.size() != expected || P.rows() != x.size() || P.cols() != x.size()) {
    throw std::invalid_argument("covariance uncertainty: " + std::to_string(x.size()) + " values and a " +
                                std::to_string(P.rows()) + " x " + std::to_string(P.cols()) + " covariance for " +
                                std::to_string(expected) + (linear ? " coefficients" : " parameters"));
  }
  CovarianceUncertainty u;
  for (int e = 0; e < static_cast<int>(model.bodies().size()); ++e) {
    const EstimatedBody& body = model.bodies()[e];
    Matrix10 C;
    InertialParams pi;
    if (linear) {  // x = w: the tree body's pi and its covariance block directly
      C = P.block<10, 10>(10 * body.block, 10 * body.block);
      pi = InertialParams::FromVector(x.segment<10>(10 * body.block));
    } else {
      Matrix10 J;
      body.map.ToPi(x.segment<10>(10 * e), &J);
      const Matrix10 L = ReportFrameMap(body);
      C = L * J * P.block<10, 10>(10 * e, 10 * e) * J.transpose() * L.transpose();
      pi = model.BodyInertia(e, x);
    }
    u.bodies.push_back(pi);
    u.body_pi_covariance.push_back(C);
    u.body_stds.push_back(pi.mass() > 0.0 ? UncertaintyOf(pi, C) : BodyUncertainty{});
  }
  for (int k = 0; k < static_cast<int>(model.effects().size()); ++k) {
    u.effects.push_back(linear ? LinearEffectStds(model.effects()[k], x, P) : ParameterEffectStds(model, k, x, P));
  }
  return u;
}

}  // namespace inertial
