#include "inertial/estimation/parameter_layout.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "inertial/inertia/assert.hpp"

namespace inertial {

ParameterLayout::ParameterLayout(int num_features, std::vector<BodyBlock> bodies, std::vector<ScalarBlock> scalars)
    : num_features_(num_features), bodies_(std::move(bodies)), scalars_(std::move(scalars)) {
  std::vector<int> owner;
  auto claim = [&](int parameter, int count, int feature, int feature_count, const std::string& what) {
    if (feature < 0 || feature + feature_count > num_features_) {
      throw std::invalid_argument("parameter layout: " + what + " features [" + std::to_string(feature) + ", " +
                                  std::to_string(feature + feature_count) + ") outside [0, " +
                                  std::to_string(num_features_) + ")");
    }
    if (parameter < 0) throw std::invalid_argument("parameter layout: " + what + " has a negative parameter index");
    if (static_cast<int>(owner.size()) < parameter + count) owner.resize(parameter + count, 0);
    for (int k = parameter; k < parameter + count; ++k) {
      if (owner[k]++ != 0) throw std::invalid_argument("parameter layout: parameter " + std::to_string(k) + " used twice");
    }
  };
  for (size_t b = 0; b < bodies_.size(); ++b) claim(bodies_[b].parameter, 10, bodies_[b].feature, 10, "body " + std::to_string(b));
  for (size_t s = 0; s < scalars_.size(); ++s) {
    claim(scalars_[s].parameter, scalars_[s].size(), scalars_[s].feature, scalars_[s].size(), "scalar " + std::to_string(s));
  }
  for (size_t k = 0; k < owner.size(); ++k) {
    if (owner[k] == 0) throw std::invalid_argument("parameter layout: parameter " + std::to_string(k) + " is unused");
  }
  num_parameters_ = static_cast<int>(owner.size());
}

ParameterLayout ParameterLayout::FromRobot(const RobotDynamics& model) {
  std::vector<BodyBlock> bodies;
  for (size_t e = 0; e < model.bodies().size(); ++e) {
    bodies.push_back(BodyBlock{model.bodies()[e].map, 10 * model.bodies()[e].block, static_cast<int>(10 * e)});
  }
  std::vector<ScalarBlock> scalars;
  for (const EffectTerm& t : model.effects()) {
    const ScalarMap map = t.kind == EffectKind::kOffset ? ScalarMap::kLinear
                          : t.kind == EffectKind::kSpring ? ScalarMap::kSpring
                                                          : ScalarMap::kExponential;
    scalars.push_back(ScalarBlock{map, t.first_feature, t.first_parameter});
    if (t.kind == EffectKind::kAsymmetric) {  // its second coefficient: e^s too
      scalars.push_back(ScalarBlock{ScalarMap::kExponential, t.first_feature + 1, t.first_parameter + 1});
    }
  }
  return ParameterLayout(model.num_features(), std::move(bodies), std::move(scalars));
}

ParameterLayout ParameterLayout::SingleBody(const InertialParams& prior) {
  return ParameterLayout(10, {BodyBlock{LogCholeskyParameterization(prior), 0, 0}}, {});
}

void ParameterLayout::Coefficients(const Eigen::VectorXd& x, Eigen::Ref<Eigen::VectorXd> w) const {
  INERTIAL_ASSERT(x.size() == num_parameters_ && w.size() == num_features_);
  w.setZero();
  for (const BodyBlock& b : bodies_) w.segment<10>(b.feature) += b.map.ToPi(x.segment<10>(b.parameter));
  for (const ScalarBlock& s : scalars_) {
    const double v = x[s.parameter];
    switch (s.map) {
      case ScalarMap::kLinear: w[s.feature] = v; break;
      case ScalarMap::kExponential: w[s.feature] = std::exp(v); break;
      case ScalarMap::kSpring:
        w[s.feature] = std::exp(v);
        w[s.feature + 1] = std::exp(v) * x[s.parameter + 1];
        break;
    }
  }
}

void ParameterLayout::Evaluate(const Eigen::VectorXd& x, const Eigen::MatrixXd& A, Eigen::Ref<Eigen::VectorXd> w,
                               Eigen::Ref<Eigen::MatrixXd> H) const {
  INERTIAL_ASSERT(x.size() == num_parameters_ && w.size() == num_features_ && A.cols() == num_features_);
  INERTIAL_ASSERT(H.rows() == A.rows() && H.cols() == num_parameters_);
  w.setZero();
  Matrix10 J;
  for (const BodyBlock& b : bodies_) {
    w.segment<10>(b.feature) += b.map.ToPi(x.segment<10>(b.parameter), &J);
    // Row by row, a fixed-size 10 x 10 product (J^T a); a row of A that is zero over the body (a
    // joint that does not carry it: a robot's regressor is block-triangular) gives a zero row.
    for (Eigen::Index i = 0; i < A.rows(); ++i) {
      const Vector10 a = A.row(i).segment<10>(b.feature).transpose();
      if ((a.array() == 0.0).all()) {
        H.row(i).segment<10>(b.parameter).setZero();
      } else {
        // Coefficient-based (lazyProduct): unrolled dot products, not a call into Eigen's GEMV.
        H.row(i).segment<10>(b.parameter).noalias() = a.transpose().lazyProduct(J);
      }
    }
  }
  for (const ScalarBlock& s : scalars_) {
    const double v = x[s.parameter];
    switch (s.map) {
      case ScalarMap::kLinear:
        w[s.feature] = v;
        H.col(s.parameter) = A.col(s.feature);
        break;
      case ScalarMap::kExponential:
        w[s.feature] = std::exp(v);
        H.col(s.parameter) = w[s.feature] * A.col(s.feature);
        break;
      case ScalarMap::kSpring: {
        const double k = std::exp(v), q0 = x[s.parameter + 1];
        w[s.feature] = k;
        w[s.feature + 1] = k * q0;
        // d(k a0 + k q0 a1)/ds = k a0 + k q0 a1, d/dq0 = k a1.
        H.col(s.parameter) = k * A.col(s.feature) + k * q0 * A.col(s.feature + 1);
        H.col(s.parameter + 1) = k * A.col(s.feature + 1);
        break;
      }
    }
  }
}

InertialParams ParameterLayout::Body(int b, const Eigen::VectorXd& x) const {
  const BodyBlock& block = bodies_.at(b);
  return InertialParams::FromVector(block.map.ToPi(x.segment<10>(block.parameter)));
}

Matrix10 ParameterLayout::BodyCovariance(int b, const Eigen::VectorXd& x, const Eigen::MatrixXd& P) const {
  const BodyBlock& block = bodies_.at(b);
  Matrix10 J;
  block.map.ToPi(x.segment<10>(block.parameter), &J);
  const Matrix10 Pbb = P.block<10, 10>(block.parameter, block.parameter);
  return J * Pbb * J.transpose();
}

BodyUncertainty UncertaintyOf(const InertialParams& body, const Matrix10& C) {
  BodyUncertainty u;
  const double m = body.mass();
  const Vector3 h = body.first_moment();
  u.mass = std::sqrt(std::max(0.0, C(0, 0)));
  Eigen::Matrix<double, 3, 10> G = Eigen::Matrix<double, 3, 10>::Zero();
  G.col(0) = -h / (m * m);
  G.block<3, 3>(0, 1) = Matrix3::Identity() / m;
  u.com = (G * C * G.transpose()).diagonal().cwiseMax(0.0).cwiseSqrt();
  u.inertia = C.diagonal().tail<6>().cwiseMax(0.0).cwiseSqrt();
  Matrix10 J_mci_pi;
  MassComInertiaAboutCom(body, &J_mci_pi);
  const Eigen::Matrix<double, 6, 10> G_IC = J_mci_pi.middleRows<6>(mci_index::kIxx);
  u.inertia_about_com = (G_IC * C * G_IC.transpose()).diagonal().cwiseMax(0.0).cwiseSqrt();
  return u;
}

Vector10 MassComInertiaAboutCom(const InertialParams& body, Matrix10* J_mci_pi) {
  const double m = body.mass();
  INERTIAL_ASSERT(m != 0.0);
  const Vector3 h = body.first_moment();
  const Matrix3 I_C = body.rotational_inertia_about_com();
  // The six tensor entries in pi's order: (0,0), (1,1), (2,2), (0,1), (1,2), (0,2).
  constexpr int kRow[6] = {0, 1, 2, 0, 1, 0};
  constexpr int kCol[6] = {0, 1, 2, 1, 2, 2};
  Vector10 mci;
  mci[mci_index::kMass] = m;
  mci.segment<3>(mci_index::kCx) = h / m;
  for (int e = 0; e < 6; ++e) mci[mci_index::kIxx + e] = I_C(kRow[e], kCol[e]);
  if (J_mci_pi != nullptr) {
    Matrix10& J = *J_mci_pi;
    J.setZero();
    J(mci_index::kMass, pi_index::kMass) = 1.0;
    J.block<3, 1>(mci_index::kCx, pi_index::kMass) = -h / (m * m);
    J.block<3, 3>(mci_index::kCx, pi_index::kHx) = Matrix3::Identity() / m;
    const double hh = h.squaredNorm();
    for (int e = 0; e < 6; ++e) {
      const int i = kRow[e], j = kCol[e], row = mci_index::kIxx + e;
      const double delta_ij = i == j ? 1.0 : 0.0;
      // Shift S_ij = (|h|^2 delta_ij - h_i h_j) / m, I_C = I_O - S.
      J(row, pi_index::kMass) = (hh * delta_ij - h[i] * h[j]) / (m * m);
      for (int k = 0; k < 3; ++k) {
        const double dS_dhk = (2.0 * h[k] * delta_ij - (i == k ? h[j] : 0.0) - (j == k ? h[i] : 0.0)) / m;
        J(row, pi_index::kHx + k) = -dS_dhk;
      }
      J(row, pi_index::kIxx + e) = 1.0;
    }
  }
  return mci;
}

}  // namespace inertial
