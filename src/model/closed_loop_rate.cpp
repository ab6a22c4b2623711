#include "inertial/model/closed_loop_rate.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace inertial {
namespace {

// Forward-difference step for a coordinate of magnitude |x|: sqrt(machine epsilon) relative, the
// step that balances truncation and rounding for a smooth function.
double DifferenceStep(double x) {
  return std::sqrt(std::numeric_limits<double>::epsilon()) * std::max(1.0, std::abs(x));
}

void CheckSize(const Eigen::VectorXd& v, Eigen::Index n, const char* what) {
  if (v.size() != n) {
    throw std::invalid_argument(std::string("closed-loop rate: ") + what + " has " + std::to_string(v.size()) +
                                " entries for " + std::to_string(n) + " joints");
  }
}

}  // namespace

CommandSlopes PdCommandSlopes(const Eigen::VectorXd& kp, const Eigen::VectorXd& kd) {
  if (kp.size() != kd.size()) {
    throw std::invalid_argument("closed-loop rate: kp and kd have " + std::to_string(kp.size()) + " and " +
                                std::to_string(kd.size()) + " entries");
  }
  CommandSlopes s;
  s.dq = -kp.asDiagonal().toDenseMatrix();
  s.dqd = -kd.asDiagonal().toDenseMatrix();
  return s;
}

CommandSlopes DifferencedCommandSlopes(const JointControllerFn& controller, double t, const Eigen::VectorXd& q,
                                       const Eigen::VectorXd& qd, const Eigen::VectorXd& tau) {
  const Eigen::Index n = q.size();
  CheckSize(qd, n, "qd");
  CheckSize(tau, n, "the command");
  CommandSlopes s;
  s.dq.resize(n, n);
  s.dqd.resize(n, n);
  Eigen::VectorXd x = q;
  for (Eigen::Index k = 0; k < n; ++k) {
    const double step = DifferenceStep(q[k]);
    x[k] = q[k] + step;
    const Eigen::VectorXd moved = controller(t, x, qd);
    CheckSize(moved, n, "the controller's command");
    s.dq.col(k) = (moved - tau) / (x[k] - q[k]);  // the step as represented
    x[k] = q[k];
  }
  Eigen::VectorXd v = qd;
  for (Eigen::Index k = 0; k < n; ++k) {
    const double step = DifferenceStep(qd[k]);
    v[k] = qd[k] + step;
    const Eigen::VectorXd moved = controller(t, q, v);
    CheckSize(moved, n, "the controller's command");
    s.dqd.col(k) = (moved - tau) / (v[k] - qd[k]);
    v[k] = qd[k];
  }
  return s;
}

PlantSlopes DifferencedPlantSlopes(const JointDynamicsFn& plant, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                                   const Eigen::VectorXd& qdd) {
  const Eigen::Index n = q.size();
  CheckSize(qd, n, "qd");
  CheckSize(qdd, n, "qdd");
  const Eigen::VectorXd tau0 = plant(q, qd, qdd);
  CheckSize(tau0, n, "the plant's torque");
  PlantSlopes s;
  s.dq.resize(n, n);
  s.dqd.resize(n, n);
  Eigen::VectorXd x = q;
  for (Eigen::Index k = 0; k < n; ++k) {
    x[k] = q[k] + DifferenceStep(q[k]);
    const Eigen::VectorXd moved = plant(x, qd, qdd);
    CheckSize(moved, n, "the plant's torque");
    s.dq.col(k) = (moved - tau0) / (x[k] - q[k]);
    x[k] = q[k];
  }
  Eigen::VectorXd v = qd;
  for (Eigen::Index k = 0; k < n; ++k) {
    v[k] = qd[k] + DifferenceStep(qd[k]);
    const Eigen::VectorXd moved = plant(q, v, qdd);
    CheckSize(moved, n, "the plant's torque");
    s.dqd.col(k) = (moved - tau0) / (v[k] - qd[k]);
    v[k] = qd[k];
  }
  return s;
}

Eigen::MatrixXd LoopJacobian(const Eigen::LLT<Eigen::MatrixXd>& mass, const PlantSlopes& plant,
                             const CommandSlopes& command) {
  const Eigen::Index n = mass.rows();
  for (const Eigen::MatrixXd* m : {&plant.dq, &plant.dqd, &command.dq, &command.dqd}) {
    if (m->rows() != n || m->cols() != n) {
      throw std::invalid_argument("closed-loop rate: slopes of " + std::to_string(m->rows()) + " x " +
                                  std::to_string(m->cols()) + " for a " + std::to_string(n) + " x " +
                                  std::to_string(n) + " mass matrix");
    }
  }
  Eigen::MatrixXd G(n, 2 * n);
  G << command.dq - plant.dq, command.dqd - plant.dqd;
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(2 * n, 2 * n);
  J.topRightCorner(n, n).setIdentity();
  J.bottomRows(n) = mass.solve(G);
  return J;
}

Eigen::MatrixXd ClosedLoopJacobian(const JointDynamicsFn& plant, const Eigen::LLT<Eigen::MatrixXd>& mass,
                                   const Eigen::VectorXd& q, const Eigen::VectorXd& qd, const Eigen::VectorXd& qdd,
                                   const CommandSlopes& command) {
  return LoopJacobian(mass, DifferencedPlantSlopes(plant, q, qd, qdd), command);
}

double StepRate(const Eigen::LLT<Eigen::MatrixXd>& mass, const PlantSlopes& plant, const CommandSlopes& command) {
  const Eigen::Index n = mass.rows();
  CommandSlopes held;
  held.dq = Eigen::MatrixXd::Zero(n, n);
  held.dqd = Eigen::MatrixXd::Zero(n, n);
  return std::max(SpectralRadius(LoopJacobian(mass, plant, held)), SpectralRadius(LoopJacobian(mass, plant, command)));
}

double SpectralRadius(const Eigen::MatrixXd& a) {
  if (a.rows() != a.cols()) {
    throw std::invalid_argument("spectral radius: the matrix is " + std::to_string(a.rows()) + " x " +
                                std::to_string(a.cols()));
  }
  if (a.size() == 0) return 0.0;
  if (!a.allFinite()) return std::numeric_limits<double>::infinity();
  const Eigen::EigenSolver<Eigen::MatrixXd> eig(a, /*computeEigenvectors=*/false);
  if (eig.info() != Eigen::Success) return std::numeric_limits<double>::infinity();
  return eig.eigenvalues().cwiseAbs().maxCoeff();
}

namespace {

void CheckSamplePeriod(double sample_period) {
  if (!std::isfinite(sample_period) || sample_period <= 0.0) {
    throw std::invalid_argument("steps per sample: the sample period must be positive and finite, got " +
                                std::to_string(sample_period));
  }
}

}  // namespace

double MaxStepsPerSample(double sample_period) {
  CheckSamplePeriod(sample_period);
  // The relative allowance keeps a whole T / kShortestStep from rounding down past itself.
  return std::clamp(std::floor(sample_period / kShortestStep * (1.0 + 1e-12)), 1.0, 1e9);
}

double StepsPerSample(double sample_period, double rho, int base_steps) {
  CheckSamplePeriod(sample_period);
  if (base_steps < 1) throw std::invalid_argument("steps per sample: base_steps must be >= 1");
  if (std::isnan(rho) || rho < 0.0) {
    throw std::invalid_argument("steps per sample: the closed-loop rate must be >= 0, got " + std::to_string(rho));
  }
  if (!std::isfinite(rho)) return std::numeric_limits<double>::infinity();
  // The small relative allowance keeps T rho / c a whole number from rounding up past itself.
  const double needed = std::ceil(sample_period * rho / kStepRateLimit * (1.0 - 1e-12));
  return std::max(static_cast<double>(base_steps), needed);
}

}  // namespace inertial
