#include "inertial/inertia/bounding_ellipsoid.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace inertial {

BoundingEllipsoid BoundingEllipsoid::FromAxes(const Vector3& center, const Matrix3& axes, const Vector3& semi_axes) {
  for (int i = 0; i < 3; ++i) {
    if (!(semi_axes[i] > 0.0) || !std::isfinite(semi_axes[i])) {
      throw std::invalid_argument("ellipsoid: semi-axis " + std::to_string(i) + " is not positive and finite");
    }
  }
  BoundingEllipsoid e;
  e.center = center;
  e.shape_inverse = axes * semi_axes.cwiseAbs2().cwiseInverse().asDiagonal() * axes.transpose();
  return e;
}

Vector3 BoundingEllipsoid::SemiAxes() const {
  const Eigen::SelfAdjointEigenSolver<Matrix3> eig(shape_inverse);
  // Largest eigenvalue of P first: its semi-axis is the shortest.
  return Vector3(1.0 / std::sqrt(eig.eigenvalues()[2]), 1.0 / std::sqrt(eig.eigenvalues()[1]),
                 1.0 / std::sqrt(eig.eigenvalues()[0]));
}

double BoundingEllipsoid::Volume() const { return 4.0 / 3.0 * M_PI / std::sqrt(shape_inverse.determinant()); }

bool BoundingEllipsoid::Contains(const Vector3& x) const {
  const Vector3 d = x - center;
  return d.dot(shape_inverse * d) <= 1.0 + 1e-12;
}

BoundingEllipsoid BoundingEllipsoid::Scaled(double factor) const {
  BoundingEllipsoid e = *this;
  e.shape_inverse /= factor * factor;
  return e;
}

Matrix4 BoundingEllipsoid::Q() const {
  Matrix4 q;
  const Vector3 Pc = shape_inverse * center;
  q.topLeftCorner<3, 3>() = -shape_inverse;
  q.topRightCorner<3, 1>() = Pc;
  q.bottomLeftCorner<1, 3>() = Pc.transpose();
  q(3, 3) = 1.0 - center.dot(Pc);
  return q;
}

Vector10 BoundingEllipsoid::RegionCoefficients() const {
  const Matrix4 q = Q();
  Vector10 coefficients;
  for (int i = 0; i < 10; ++i) coefficients[i] = (q * PseudoInertiaFromPi(Vector10::Unit(i))).trace();
  return coefficients;
}

double BoundingEllipsoid::Slack(const InertialParams& body) const {
  if (!(body.mass() > 0.0)) return -std::numeric_limits<double>::infinity();
  return RegionCoefficients().dot(body.vector()) / body.mass();
}

BoundingEllipsoid MinimumVolumeEllipsoid(const std::vector<Vector3>& points, double tolerance) {
  const int n = static_cast<int>(points.size());
  if (n < 4) throw std::invalid_argument("bounding ellipsoid: at least 4 points are needed, got " + std::to_string(n));
  for (int i = 0; i < n; ++i) {
    if (!points[i].allFinite()) throw std::invalid_argument("bounding ellipsoid: point " + std::to_string(i) + " is not finite");
  }
  // Khachiyan's iteration on the lifted points [p; 1] with Todd and Yildirim's away steps (file
  // comment): weight moves to the point of largest M_i = q_i^T X^-1 q_i, or away from the weighted
  // point of smallest M_i, whichever is further from d + 1 = 4; without away steps the iteration
  // needs thousands of steps per region, with them tens to hundreds.
  std::vector<Vector4> lifted(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) lifted[static_cast<size_t>(i)] << points[static_cast<size_t>(i)], 1.0;
  Eigen::VectorXd u = Eigen::VectorXd::Constant(n, 1.0 / n), M(n);
  for (int iteration = 0; iteration < 100000; ++iteration) {
    Matrix4 X = Matrix4::Zero();
    for (int i = 0; i < n; ++i) X.noalias() += u[i] * lifted[static_cast<size_t>(i)] * lifted[static_cast<size_t>(i)].transpose();
    const Eigen::LLT<Matrix4> llt(X);
    const Vector4 diagonal = llt.matrixL().toDenseMatrix().diagonal();
    if (llt.info() != Eigen::Success || !(diagonal.minCoeff() > 1e-7 * diagonal.maxCoeff())) {
      throw std::invalid_argument("bounding ellipsoid: the points lie in a plane");
    }
    const Matrix4 X_inv = llt.solve(Matrix4::Identity());
    int up = 0, down = -1;
    for (int i = 0; i < n; ++i) {
      M[i] = lifted[static_cast<size_t>(i)].dot(X_inv * lifted[static_cast<size_t>(i)]);
      if (M[i] > M[up]) up = i;
      if (u[i] > 0.0 && (down < 0 || M[i] < M[down])) down = i;
    }
    const double plus = M[up] / 4.0 - 1.0, minus = 1.0 - M[down] / 4.0;
    if (std::max(plus, minus) <= tolerance) break;
    if (plus >= minus) {
      const double step = (M[up] - 4.0) / (4.0 * (M[up] - 1.0));
      u *= 1.0 - step;
      u[up] += step;
    } else {
      const double step = std::min((4.0 - M[down]) / (4.0 * (M[down] - 1.0)), u[down] / (1.0 - u[down]));
      u *= 1.0 + step;
      u[down] -= step;
      u[down] = std::max(u[down], 0.0);
    }
  }
  Vector3 c = Vector3::Zero();
  for (int i = 0; i < n; ++i) c += u[i] * points[i];
  Matrix3 spread = Matrix3::Zero();
  for (int i = 0; i < n; ++i) spread.noalias() += u[i] * (points[i] - c) * (points[i] - c).transpose();
  const Eigen::LDLT<Matrix3> ldlt(spread);
  if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().minCoeff() > 1e-14 * ldlt.vectorD().maxCoeff())) {
    throw std::invalid_argument("bounding ellipsoid: the points lie in a plane");
  }
  BoundingEllipsoid e;
  e.center = c;
  e.shape_inverse = ldlt.solve(Matrix3::Identity()) / 3.0;
  e.shape_inverse = 0.5 * (e.shape_inverse + e.shape_inverse.transpose()).eval();
  // Stopped at the tolerance, a point may lie just outside: grow to hold every point exactly.
  double worst = 0.0;
  for (const Vector3& p : points) worst = std::max(worst, (p - c).dot(e.shape_inverse * (p - c)));
  if (worst > 1.0) e.shape_inverse /= worst * (1.0 + 1e-12);
  return e;
}

BoundingEllipsoid EquivalentUniformEllipsoid(const InertialParams& body) {
  const double m = body.mass();
  if (!(m > 0.0)) throw std::invalid_argument("equivalent ellipsoid: the mass is not positive");
  const Vector3 c = body.com();
  const Matrix3 sigma_c = body.second_moments_about_origin() - m * c * c.transpose();
  const Eigen::SelfAdjointEigenSolver<Matrix3> eig(sigma_c / m);
  if (eig.info() != Eigen::Success || !(eig.eigenvalues().minCoeff() > 0.0)) {
    throw std::invalid_argument("equivalent ellipsoid: the second moment about the COM is not positive definite");
  }
  // A solid uniform ellipsoid of semi-axis a along a direction has second moment a^2 / 5 per unit
  // mass along it.
  return BoundingEllipsoid::FromAxes(c, eig.eigenvectors(), (5.0 * eig.eigenvalues()).cwiseSqrt());
}

}  // namespace inertial
