#include "inertial/diagnosis/friction_shape.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace inertial {
namespace {

// The part of column g orthogonal to qd and 1, by the 2 x 2 normal equations of [qd 1].
class Projector {
 public:
  explicit Projector(const Eigen::VectorXd& qd) : qd_(qd) {
    Eigen::Matrix2d G;
    G << qd.squaredNorm(), qd.sum(), qd.sum(), static_cast<double>(qd.size());
    G.diagonal() += Eigen::Vector2d::Constant(1e-12 * G.diagonal().maxCoeff() + 1e-300);
    G_inv_ = G.inverse();
  }
  Eigen::VectorXd operator()(const Eigen::VectorXd& g) const {
    const Eigen::Vector2d c = G_inv_ * Eigen::Vector2d(qd_.dot(g), g.sum());
    return (g - c[0] * qd_).array() - c[1];
  }

 private:
  const Eigen::VectorXd& qd_;
  Eigen::Matrix2d G_inv_;
};

// The fall of ||r||^2 from one feature with a non-negative level.
double OneColumnGain(const Eigen::VectorXd& g, const Eigen::VectorXd& r) {
  const double gg = g.squaredNorm(), gr = g.dot(r);
  return gg > 0.0 && gr > 0.0 ? gr * gr / gg : 0.0;
}

// The fall of ||r||^2 from two features with non-negative levels (the best of: both free, equal
// levels, either alone; so never less than the symmetric step a + b explains).
double TwoColumnGain(const Eigen::VectorXd& a, const Eigen::VectorXd& b, const Eigen::VectorXd& r) {
  double best = std::max({OneColumnGain(a, r), OneColumnGain(b, r), OneColumnGain(a + b, r)});
  Eigen::Matrix2d M;
  M << a.squaredNorm(), a.dot(b), a.dot(b), b.squaredNorm();
  const Eigen::Vector2d c(a.dot(r), b.dot(r));
  const double det = M.determinant();
  if (det > 1e-12 * M(0, 0) * M(1, 1)) {
    const Eigen::Vector2d level = M.inverse() * c;
    if (level.minCoeff() >= 0.0) best = std::max(best, c.dot(level));
  }
  return best;
}

}  // namespace

int FrictionShapeParameters(EffectKind kind) {
  if (kind == EffectKind::kCoulomb || kind == EffectKind::kAsymmetric) return 1;
  if (kind == EffectKind::kSigmoid) return 2;
  return 0;
}

FrictionShape FitFrictionShape(EffectKind kind, const std::string& joint, const Eigen::VectorXd& qd,
                               const Eigen::VectorXd& residual) {
  if (FrictionShapeParameters(kind) == 0) {
    throw std::invalid_argument("friction shape: " + std::string(ToString(kind)) + " has no shape to fit");
  }
  if (qd.size() != residual.size() || qd.size() < 3) {
    throw std::invalid_argument("friction shape of " + joint + ": " + std::to_string(qd.size()) + " velocities and " +
                                std::to_string(residual.size()) + " residuals (equal, at least 3)");
  }
  if (!qd.allFinite() || !residual.allFinite()) {
    throw std::invalid_argument("friction shape of " + joint + ": velocities or residuals are not finite");
  }
  FrictionShape best;
  best.spec.kind = kind;
  best.spec.target = joint;
  best.spec.text = std::string(ToString(kind)) + "@" + joint;
  const double rms = std::sqrt(qd.squaredNorm() / static_cast<double>(qd.size()));
  if (!(rms > 0.0)) return best;  // a joint that never moves: no shape to see
  const Projector project(qd);
  const Eigen::VectorXd r = project(residual);
  constexpr double kShifts[] = {-2.0, -1.0, -0.5, 0.0, 0.5, 1.0, 2.0};  // p2 p3
  bool first = true;
  for (int k = 1; k <= 10; ++k) {
    const double v = rms * std::ldexp(1.0, -k);
    auto consider = [&](double gain, const EffectSpec& spec) {
      if (first || gain > best.gain) {
        best.gain = gain;
        best.spec.velocity_scale = spec.velocity_scale;
        best.spec.steepness = spec.steepness;
        best.spec.shift = spec.shift;
        first = false;
      }
    };
    EffectSpec spec = best.spec;
    spec.velocity_scale = v;
    if (kind == EffectKind::kCoulomb) {
      consider(OneColumnGain(project((qd / v).array().tanh().matrix()), r), spec);
    } else if (kind == EffectKind::kAsymmetric) {
      const Eigen::ArrayXd s = (qd / v).array().tanh();
      consider(TwoColumnGain(project(s.max(0.0).matrix()), project(s.min(0.0).matrix()), r), spec);
    } else {
      spec.steepness = 2.0 / v;
      for (double u : kShifts) {
        spec.shift = u / spec.steepness;
        Eigen::VectorXd g(qd.size());
        for (int i = 0; i < qd.size(); ++i) g[i] = SigmoidFriction(qd[i], spec.steepness, spec.shift);
        consider(OneColumnGain(project(g), r), spec);
      }
    }
  }
  return best;
}

}  // namespace inertial
