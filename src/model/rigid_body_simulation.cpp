#include "inertial/model/rigid_body_simulation.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>

#include "inertial/inertia/assert.hpp"
#include "inertial/model/spatial_algebra.hpp"

namespace inertial {

double KineticEnergy(const InertialParams& body, const Vector6& xi) {
  return 0.5 * xi.dot(body.spatial_inertia() * xi);
}

SimulationResult SimulateRigidBody(const InertialParams& body, const Vector6& xi0,
                                   const std::function<Vector6(double)>& wrench,
                                   const std::vector<double>& sample_times, const IntegratorOptions& options) {
  SimulationResult result;
  if (sample_times.empty()) {
    result.ok = true;
    return result;
  }
  const Matrix6 M = body.spatial_inertia();
  const Eigen::LLT<Matrix6> M_llt(M);
  INERTIAL_ASSERT(M_llt.info() == Eigen::Success);  // precondition: a consistent body
  auto f = [&](double t, const Vector6& xi) -> Vector6 {
    return M_llt.solve(wrench(t) - ForceCross(xi) * (M * xi));
  };

  // Dormand-Prince 5(4).
  constexpr double c2 = 1.0 / 5, c3 = 3.0 / 10, c4 = 4.0 / 5, c5 = 8.0 / 9;
  constexpr double a21 = 1.0 / 5;
  constexpr double a31 = 3.0 / 40, a32 = 9.0 / 40;
  constexpr double a41 = 44.0 / 45, a42 = -56.0 / 15, a43 = 32.0 / 9;
  constexpr double a51 = 19372.0 / 6561, a52 = -25360.0 / 2187, a53 = 64448.0 / 6561, a54 = -212.0 / 729;
  constexpr double a61 = 9017.0 / 3168, a62 = -355.0 / 33, a63 = 46732.0 / 5247, a64 = 49.0 / 176,
                   a65 = -5103.0 / 18656;
  constexpr double b1 = 35.0 / 384, b3 = 500.0 / 1113, b4 = 125.0 / 192, b5 = -2187.0 / 6784, b6 = 11.0 / 84;
  // Error weights b - b* (5th minus 4th order).
  constexpr double e1 = 71.0 / 57600, e3 = -71.0 / 16695, e4 = 71.0 / 1920, e5 = -17253.0 / 339200,
                   e6 = 22.0 / 525, e7 = -1.0 / 40;

  double t = sample_times.front();
  Vector6 y = xi0;
  Vector6 k1 = f(t, y);
  double h = options.initial_step;
  result.twists.reserve(sample_times.size());
  result.twists.push_back(y);
  int steps = 0;
  for (std::size_t next = 1; next < sample_times.size(); ++next) {
    const double target = sample_times[next];
    while (t < target) {
      if (++steps > options.max_steps || !y.allFinite()) return result;
      const bool last = t + h >= target;
      const double step = last ? target - t : h;
      const Vector6 k2 = f(t + c2 * step, y + step * (a21 * k1));
      const Vector6 k3 = f(t + c3 * step, y + step * (a31 * k1 + a32 * k2));
      const Vector6 k4 = f(t + c4 * step, y + step * (a41 * k1 + a42 * k2 + a43 * k3));
      const Vector6 k5 = f(t + c5 * step, y + step * (a51 * k1 + a52 * k2 + a53 * k3 + a54 * k4));
      const Vector6 k6 = f(t + step, y + step * (a61 * k1 + a62 * k2 + a63 * k3 + a64 * k4 + a65 * k5));
      const Vector6 y_new = y + step * (b1 * k1 + b3 * k3 + b4 * k4 + b5 * k5 + b6 * k6);
      const Vector6 k7 = f(t + step, y_new);
      const Vector6 err = step * (e1 * k1 + e3 * k3 + e4 * k4 + e5 * k5 + e6 * k6 + e7 * k7);
      const Vector6 scale = (options.absolute_tolerance +
                             options.relative_tolerance * y.cwiseAbs().cwiseMax(y_new.cwiseAbs()).array())
                                .matrix();
      const double err_norm = std::sqrt((err.cwiseQuotient(scale)).squaredNorm() / 6.0);
      const double factor = err_norm > 0.0 ? std::clamp(0.9 * std::pow(err_norm, -0.2), 0.2, 5.0) : 5.0;
      if (err_norm <= 1.0) {
        t = last ? target : t + step;
        y = y_new;
        k1 = k7;  // first same as last
        ++result.accepted_steps;
        if (!last) h = step * factor;
        else h = std::max(h, step * factor);  // a short landing step does not shrink h
      } else {
        ++result.rejected_steps;
        h = step * std::min(1.0, factor);
      }
    }
    result.twists.push_back(y);
  }
  result.ok = y.allFinite();
  return result;
}

}  // namespace inertial
