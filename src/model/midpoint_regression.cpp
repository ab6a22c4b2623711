#include "inertial/model/midpoint_regression.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "inertial/inertia/assert.hpp"
#include "inertial/model/rigid_body_regressor.hpp"

namespace inertial {

void MidpointRegressorPair(const TwistWrenchSample& s0, const TwistWrenchSample& s1, const Vector3& g_B,
                           Matrix6x10* Y, Vector6* w) {
  const double dt = s1.t - s0.t;
  INERTIAL_ASSERT(dt > 0.0);
  const Vector6 xi_dot = (s1.twist - s0.twist) / dt;
  const Vector6 xi_bar = 0.5 * (s1.twist + s0.twist);
  *Y = RigidBodyRegressor(xi_bar, xi_dot, g_B);
  *w = 0.5 * (s0.wrench + s1.wrench);
}

LinearRegression BuildMidpointRegression(const std::vector<TwistWrenchSample>& samples, const Vector3& g_B) {
  if (samples.size() < 2) {
    throw std::invalid_argument("single-body regression needs at least two samples, got " +
                                std::to_string(samples.size()));
  }
  if (!g_B.allFinite()) throw std::invalid_argument("gravity vector is not finite");
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const TwistWrenchSample& s = samples[i];
    if (!std::isfinite(s.t) || !s.twist.allFinite() || !s.wrench.allFinite()) {
      throw std::invalid_argument("sample " + std::to_string(i) + ": non-finite time, twist or wrench");
    }
    if (i > 0 && !(s.t > samples[i - 1].t)) {
      std::ostringstream os;
      os.precision(17);
      os << "sample " << i << ": time " << s.t << " s does not increase (previous sample at " << samples[i - 1].t
         << " s)";
      throw std::invalid_argument(os.str());
    }
  }
  const Eigen::Index pairs = static_cast<Eigen::Index>(samples.size()) - 1;
  LinearRegression reg;
  reg.A.resize(6 * pairs, 10);
  reg.b.resize(6 * pairs);
  Matrix6x10 Y;
  Vector6 w;
  for (Eigen::Index i = 0; i < pairs; ++i) {
    MidpointRegressorPair(samples[i], samples[i + 1], g_B, &Y, &w);
    reg.A.block<6, 10>(6 * i, 0) = Y;
    reg.b.segment<6>(6 * i) = w;
  }
  return reg;
}

}  // namespace inertial
