/// @file parameter_layout.hpp
/// How an estimator's parameters x map to the coefficients w of a model linear in them,
/// y = A w(x) (the joint-torque regressor with effects, or one body's Newton-Euler regressor):
///   - body blocks: w[f .. f+10) += pi(theta), theta = x[p .. p+10), log-Cholesky relative to a
///     prior (eq. 11), so every x is a fully physically consistent body;
///   - scalar blocks: w[f] = x[p] (linear, e.g. an offset), w[f] = e^{x[p]} (a non-negative
///     coefficient, as the paper does for friction), or a spring (w[f] = e^{x[p]},
///     w[f+1] = e^{x[p]} x[p+1]).
/// J_w_x is block diagonal; H = A J_w_x is formed block by block (each row of A over a body times
/// its 10 x 10 Jacobian, skipping the rows that are zero over the body), never as a dense product. Evaluate() allocates nothing and throws nothing.
/// Conventions: pi and theta orders of types.hpp; SI units.
#pragma once

#include <vector>

#include "inertial/inertia/log_cholesky.hpp"
#include "inertial/model/robot_dynamics.hpp"

namespace inertial {

struct BodyBlock {
  LogCholeskyParameterization map;  ///< relative to the body's prior
  int feature = 0;                  ///< first of the 10 coefficients it adds to
  int parameter = 0;                ///< first of its 10 parameters (theta)
};

enum class ScalarMap { kLinear, kExponential, kSpring };

struct ScalarBlock {
  ScalarMap map = ScalarMap::kLinear;
  int feature = 0;
  int parameter = 0;
  int size() const { return map == ScalarMap::kSpring ? 2 : 1; }
};

/// Indices into mci = [m, cx, cy, cz, ICxx, ICyy, ICzz, ICxy, ICyz, ICxz]: mass [kg], center of
/// mass c = h / m [m] and rotational inertia about the COM I_C [kg m^2] (entries in pi's order,
/// ICxy the (0,1) entry of the tensor, as InertialParams::rotational_inertia_about_com()).
namespace mci_index {
inline constexpr int kMass = 0;
inline constexpr int kCx = 1;   ///< cx, cy, cz at kCx .. kCx + 2
inline constexpr int kIxx = 4;  ///< ICxx, ICyy, ICzz, ICxy, ICyz, ICxz at kIxx .. kIxx + 5
}  // namespace mci_index

/// mci(pi) (indices above) with I_C = I_O - (|h|^2 1 - h h^T) / m (parallel-axis theorem), and
/// optionally its analytic Jacobian J_mci_pi = d(mci)/d(pi) (10 x 10):
///   dc/dm = -h / m^2, dc/dh = 1 / m;
///   I_C(i,j) = I_O(i,j) - (|h|^2 delta_ij - h_i h_j) / m, so dI_C(i,j)/dm = (|h|^2 delta_ij - h_i h_j) / m^2,
///   dI_C(i,j)/dh_k = -(2 h_k delta_ij - delta_ik h_j - h_i delta_jk) / m, dI_C/dI_O = 1.
/// Precondition: body.mass() != 0 (debug-asserted).
Vector10 MassComInertiaAboutCom(const InertialParams& body, Matrix10* J_mci_pi = nullptr);

/// Standard deviations of a body's physical quantities, from the covariance of its pi through the
/// Jacobian of each quantity (first order): mass [kg], COM c = h / m [m] (dc/dpi = [-h/m^2, 1/m,
/// 0]), the rotational inertia about the frame origin [Ixx Iyy Izz Ixy Iyz Ixz] [kg m^2], and the
/// rotational inertia about the COM in the same order [kg m^2] (through J_mci_pi,
/// MassComInertiaAboutCom).
struct BodyUncertainty {
  double mass = 0.0;
  Vector3 com = Vector3::Zero();
  Vector6 inertia = Vector6::Zero();
  Vector6 inertia_about_com = Vector6::Zero();
};
/// From pi and its 10 x 10 covariance. Precondition: pi's mass is positive.
BodyUncertainty UncertaintyOf(const InertialParams& body, const Matrix10& covariance_of_pi);

class ParameterLayout {
 public:
  /// @throws std::invalid_argument if a block lies outside [0, num_features) or the parameters are
  /// not numbered 0, 1, ... without gaps or overlaps.
  ParameterLayout(int num_features, std::vector<BodyBlock> bodies, std::vector<ScalarBlock> scalars);

  /// The layout of RobotDynamics' x (bodies, then effects): the same numbering.
  static ParameterLayout FromRobot(const RobotDynamics& model);
  /// One body: x = theta relative to `prior`, w = pi. @throws std::invalid_argument if the prior
  /// is not fully physically consistent.
  static ParameterLayout SingleBody(const InertialParams& prior);

  int num_parameters() const { return num_parameters_; }
  int num_features() const { return num_features_; }
  const std::vector<BodyBlock>& bodies() const { return bodies_; }
  const std::vector<ScalarBlock>& scalars() const { return scalars_; }

  /// w(x). Preconditions (debug-asserted): sizes.
  void Coefficients(const Eigen::VectorXd& x, Eigen::Ref<Eigen::VectorXd> w) const;
  /// w(x) and H = A J_w_x (A: m x num_features, H: m x num_parameters). Allocation-free.
  void Evaluate(const Eigen::VectorXd& x, const Eigen::MatrixXd& A, Eigen::Ref<Eigen::VectorXd> w,
                Eigen::Ref<Eigen::MatrixXd> H) const;
  /// Body b's pi at x (in the frame of its feature block).
  InertialParams Body(int b, const Eigen::VectorXd& x) const;
  /// Covariance of body b's pi from the covariance of x: J P_bb J^T (10 x 10).
  Matrix10 BodyCovariance(int b, const Eigen::VectorXd& x, const Eigen::MatrixXd& P) const;

 private:
  int num_features_ = 0;
  int num_parameters_ = 0;
  std::vector<BodyBlock> bodies_;
  std::vector<ScalarBlock> scalars_;
};

}  // namespace inertial
