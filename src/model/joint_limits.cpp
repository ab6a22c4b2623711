#include "inertial/model/joint_limits.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace inertial {
namespace {

void ValidateLimits(const std::vector<JointLimits>& limits) {
  for (std::size_t j = 0; j < limits.size(); ++j) {
    const JointLimits& l = limits[j];
    const std::string where = "joint limits of joint " + std::to_string(j);
    if (std::isnan(l.lower) || std::isnan(l.upper) || std::isnan(l.velocity) || std::isnan(l.effort)) {
      throw std::invalid_argument(where + ": a limit is NaN");
    }
    if (l.lower > l.upper) {
      throw std::invalid_argument(where + ": lower " + std::to_string(l.lower) + " > upper " + std::to_string(l.upper));
    }
    if (!(l.velocity > 0.0) || !(l.effort > 0.0)) {
      throw std::invalid_argument(where + ": velocity and effort limits must be positive");
    }
  }
}

}  // namespace

const char* ToString(LimitKind kind) {
  switch (kind) {
    case LimitKind::kPosition: return "position";
    case LimitKind::kVelocity: return "velocity";
    case LimitKind::kEffort: return "effort";
  }
  return "?";
}

std::vector<LimitedExcitation> FitExcitationToLimits(const std::vector<JointLimits>& limits, const Eigen::VectorXd& t,
                                                     double margin, FourierTrajectory* trajectory) {
  const int n = trajectory->num_joints();
  if (static_cast<int>(limits.size()) != n) {
    throw std::invalid_argument("FitExcitationToLimits: " + std::to_string(limits.size()) + " joint limits for " +
                                std::to_string(n) + " joints");
  }
  if (!(margin >= 0.0 && margin < 1.0)) throw std::invalid_argument("FitExcitationToLimits: margin must be in [0, 1)");
  if (t.size() == 0 || !t.allFinite()) {
    throw std::invalid_argument("FitExcitationToLimits: the sample times are empty or not finite");
  }
  ValidateLimits(limits);
  // Largest excursion and speed of every joint on the grid (independent of q0).
  Eigen::VectorXd excursion = Eigen::VectorXd::Zero(n), speed = Eigen::VectorXd::Zero(n);
  for (Eigen::Index i = 0; i < t.size(); ++i) {
    const JointTrajectoryPoint p = trajectory->Evaluate(t[i]);
    excursion = excursion.cwiseMax((p.q - trajectory->q0).cwiseAbs());
    speed = speed.cwiseMax(p.qd.cwiseAbs());
  }
  std::vector<LimitedExcitation> limited;
  for (int j = 0; j < n; ++j) {
    const JointLimits& l = limits[j];
    double scale = 1.0;
    LimitKind kind = LimitKind::kPosition;
    const bool lower = std::isfinite(l.lower), upper = std::isfinite(l.upper);
    if (lower && upper) {
      trajectory->q0[j] = 0.5 * (l.lower + l.upper);
      const double room = (1.0 - margin) * 0.5 * (l.upper - l.lower);
      if (excursion[j] > room) scale = room / excursion[j];  // room 0 (lower == upper): the joint stands
    } else if (lower) {
      trajectory->q0[j] = std::max(trajectory->q0[j], l.lower + (1.0 + margin) * excursion[j]);
    } else if (upper) {
      trajectory->q0[j] = std::min(trajectory->q0[j], l.upper - (1.0 + margin) * excursion[j]);
    }
    const double top_speed = (1.0 - margin) * l.velocity;
    if (speed[j] * scale > top_speed) {
      scale = top_speed / speed[j];
      kind = LimitKind::kVelocity;
    }
    if (scale < 1.0) {
      trajectory->a.row(j) *= scale;
      trajectory->b.row(j) *= scale;
      limited.push_back(LimitedExcitation{j, kind, scale});
    }
  }
  return limited;
}

std::optional<LimitViolation> FirstLimitViolation(const JointSamples& samples, const std::vector<JointLimits>& limits) {
  const Eigen::Index n = samples.q.cols();
  if (static_cast<Eigen::Index>(limits.size()) != n || samples.qd.cols() != n || samples.tau.cols() != n) {
    throw std::invalid_argument("FirstLimitViolation: " + std::to_string(limits.size()) + " joint limits for samples of " +
                                std::to_string(n) + " joints");
  }
  for (int i = 0; i < samples.size(); ++i) {
    for (Eigen::Index j = 0; j < n; ++j) {
      const JointLimits& l = limits[j];
      const double q = samples.q(i, j), qd = samples.qd(i, j), tau = samples.tau(i, j);
      const int joint = static_cast<int>(j);
      if (q < l.lower) return LimitViolation{joint, LimitKind::kPosition, samples.t[i], q, l.lower};
      if (q > l.upper) return LimitViolation{joint, LimitKind::kPosition, samples.t[i], q, l.upper};
      if (std::abs(qd) > l.velocity) return LimitViolation{joint, LimitKind::kVelocity, samples.t[i], qd, l.velocity};
      if (std::abs(tau) > l.effort) return LimitViolation{joint, LimitKind::kEffort, samples.t[i], tau, l.effort};
    }
  }
  return std::nullopt;
}

}  // namespace inertial
