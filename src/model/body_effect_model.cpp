#include "inertial/model/body_effect_model.hpp"

#include <stdexcept>

#include "inertial/model/rigid_body_regressor.hpp"

namespace inertial {

std::string_view ToString(BodyEffectKind kind) {
  switch (kind) {
    case BodyEffectKind::kForceBias: return "force_bias";
    case BodyEffectKind::kMomentBias: return "moment_bias";
    case BodyEffectKind::kVelocityBias: return "velocity_bias";
    case BodyEffectKind::kGravity: return "gravity";
  }
  return "?";
}

int ParameterCount(BodyEffectKind kind) { return kind == BodyEffectKind::kVelocityBias ? 6 : 3; }

std::vector<BodyEffectKind> ParseBodyEffectList(std::string_view text) {
  std::vector<BodyEffectKind> out;
  size_t start = 0;
  while (start <= text.size()) {
    const size_t comma = std::min(text.find(',', start), text.size());
    std::string_view item = text.substr(start, comma - start);
    while (!item.empty() && item.front() == ' ') item.remove_prefix(1);
    while (!item.empty() && item.back() == ' ') item.remove_suffix(1);
    if (!item.empty()) {
      bool found = false;
      for (BodyEffectKind k : {BodyEffectKind::kForceBias, BodyEffectKind::kMomentBias, BodyEffectKind::kVelocityBias,
                               BodyEffectKind::kGravity}) {
        if (item == ToString(k)) {
          for (BodyEffectKind seen : out) {
            if (seen == k) throw std::invalid_argument("'" + std::string(item) + "' is given twice");
          }
          out.push_back(k);
          found = true;
        }
      }
      if (!found) {
        throw std::invalid_argument("'" + std::string(item) +
                                    "' is not a single-body effect (force_bias, moment_bias, velocity_bias, gravity)");
      }
    } else if (comma < text.size()) {
      throw std::invalid_argument("an empty item in '" + std::string(text) + "'");
    }
    start = comma + 1;
  }
  return out;
}

BodyEffectModel::BodyEffectModel(const InertialParams& prior, std::vector<BodyEffectKind> effects)
    : prior_(prior), map_(prior), effects_(std::move(effects)) {
  for (size_t k = 0; k < effects_.size(); ++k) {
    for (size_t j = 0; j < k; ++j) {
      if (effects_[j] == effects_[k]) throw std::invalid_argument(std::string(ToString(effects_[k])) + " given twice");
    }
    first_parameter_.push_back(num_parameters_);
    num_parameters_ += ParameterCount(effects_[k]);
  }
}

std::vector<std::string> BodyEffectModel::ParameterNames() const {
  std::vector<std::string> names{"alpha", "d1", "d2", "d3", "s12", "s23", "s13", "t1", "t2", "t3"};
  for (BodyEffectKind k : effects_) {
    const std::string base(ToString(k));
    if (k == BodyEffectKind::kVelocityBias) {
      for (const char* c : {"wx", "wy", "wz", "vx", "vy", "vz"}) names.push_back(base + "." + c);
    } else {
      for (const char* c : {"x", "y", "z"}) names.push_back(base + "." + c);
    }
  }
  return names;
}

InertialParams BodyEffectModel::Body(const Eigen::VectorXd& x) const {
  return InertialParams::FromVector(map_.ToPi(x.head<10>()));
}

Eigen::VectorXd BodyEffectModel::EffectValues(int k, const Eigen::VectorXd& x) const {
  return x.segment(first_parameter_[k], ParameterCount(effects_[k]));
}

Vector6 BodyEffectModel::MeasuredPair(const BodyLog& log, int i) {
  return 0.5 * (log.samples[i].wrench + log.samples[i + 1].wrench);
}

Vector6 BodyEffectModel::PredictPair(const Eigen::VectorXd& x, const BodyLog& log, int i, Eigen::MatrixXd* J) const {
  const TwistWrenchSample& s0 = log.samples[i];
  const TwistWrenchSample& s1 = log.samples[i + 1];
  Vector6 xi = 0.5 * (s0.twist + s1.twist);
  const Vector6 xi_dot = (s1.twist - s0.twist) / (s1.t - s0.t);
  Vector3 g = log.gravity.empty() ? Vector3::Zero() : Vector3(0.5 * (log.gravity[i] + log.gravity[i + 1]));
  Vector6 bias = Vector6::Zero();
  for (size_t k = 0; k < effects_.size(); ++k) {
    const int p = first_parameter_[k];
    switch (effects_[k]) {
      case BodyEffectKind::kForceBias: bias.tail<3>() += x.segment<3>(p); break;
      case BodyEffectKind::kMomentBias: bias.head<3>() += x.segment<3>(p); break;
      case BodyEffectKind::kVelocityBias: xi -= x.segment<6>(p); break;
      case BodyEffectKind::kGravity: g += x.segment<3>(p); break;
    }
  }
  Matrix10 J_pi;
  const Vector10 pi = map_.ToPi(x.head<10>(), J != nullptr ? &J_pi : nullptr);
  const Matrix6x10 Y = RigidBodyRegressor(xi, xi_dot, g);
  const Vector6 w = Y * pi + bias;
  if (J != nullptr) {
    J->setZero(6, num_parameters_);
    J->leftCols<10>() = Y * J_pi;
    for (size_t k = 0; k < effects_.size(); ++k) {
      const int p = first_parameter_[k];
      switch (effects_[k]) {
        case BodyEffectKind::kForceBias: J->block<3, 3>(3, p).setIdentity(); break;
        case BodyEffectKind::kMomentBias: J->block<3, 3>(0, p).setIdentity(); break;
        case BodyEffectKind::kVelocityBias: {
          // The velocity-product term f(xi) = Y(xi, 0, 0) pi is quadratic in xi, so its derivative
          // along e is exactly f(xi + e) - f(xi) - f(e); w depends on xi - b_v, hence the minus.
          const Vector6 f = RigidBodyRegressor(xi, Vector6::Zero()) * pi;
          for (int c = 0; c < 6; ++c) {
            const Vector6 e = Vector6::Unit(c);
            J->col(p + c) = -(RigidBodyRegressor(xi + e, Vector6::Zero()) * pi - f -
                              RigidBodyRegressor(e, Vector6::Zero()) * pi);
          }
          break;
        }
        case BodyEffectKind::kGravity:
          // Y(xi, xi_dot, g) = Y(xi, xi_dot - [0; g], 0): linear in g.
          for (int c = 0; c < 3; ++c) {
            Vector6 a = Vector6::Zero();
            a[3 + c] = -1.0;
            J->col(p + c) = RigidBodyRegressor(Vector6::Zero(), a) * pi;
          }
          break;
      }
    }
  }
  return w;
}

Eigen::MatrixXd BodyEffectModel::Residuals(const Eigen::VectorXd& x, const BodyLog& log) const {
  Eigen::MatrixXd r(log.num_pairs(), 6);
  for (int i = 0; i < log.num_pairs(); ++i) r.row(i) = (PredictPair(x, log, i) - MeasuredPair(log, i)).transpose();
  return r;
}

}  // namespace inertial
