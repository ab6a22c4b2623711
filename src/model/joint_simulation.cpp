#include "inertial/model/joint_simulation.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>

#include "inertial/model/closed_loop_rate.hpp"
#include "inertial/model/number_text.hpp"

namespace inertial {
namespace {

constexpr double kTwoPi = 6.283185307179586476925286766559;

// Times, rates and rejected values in messages: six significant digits (number_text.hpp).
constexpr int kMessageDigits = 6;

// The sample grid and the internal step derived from the options.
struct Timing {
  int num_samples = 0;
  double sample_period = 0.0;
  int steps_per_sample = 1;
  double step = 0.0;
};

Timing CheckTiming(const JointSimulationOptions& options, bool integrating) {
  if (!std::isfinite(options.start_time)) throw std::invalid_argument("joint simulation: start_time is not finite");
  if (!std::isfinite(options.duration) || options.duration < 0.0) {
    throw std::invalid_argument("joint simulation: duration must be finite and >= 0, got " + FormatNumber(options.duration, kMessageDigits));
  }
  if (!std::isfinite(options.sample_rate_hz) || options.sample_rate_hz <= 0.0) {
    throw std::invalid_argument("joint simulation: sample_rate_hz must be positive and finite, got " +
                                FormatNumber(options.sample_rate_hz, kMessageDigits));
  }
  const double intervals = std::floor(options.duration * options.sample_rate_hz + 1e-9);
  if (intervals + 1.0 > static_cast<double>(std::numeric_limits<int>::max())) {
    throw std::invalid_argument("joint simulation: duration * sample_rate_hz is too large");
  }
  Timing timing;
  timing.num_samples = static_cast<int>(intervals) + 1;
  timing.sample_period = 1.0 / options.sample_rate_hz;
  if (integrating) {
    if (!std::isfinite(options.internal_step) || options.internal_step <= 0.0) {
      throw std::invalid_argument("joint simulation: internal_step must be positive and finite, got " +
                                  FormatNumber(options.internal_step, kMessageDigits));
    }
    const double steps = std::ceil(timing.sample_period / options.internal_step - 1e-9);
    if (steps > 1e9) throw std::invalid_argument("joint simulation: internal_step is too small for the sample rate");
    timing.steps_per_sample = std::max(1, static_cast<int>(steps));
  }
  timing.step = timing.sample_period / timing.steps_per_sample;
  return timing;
}

JointSamples Allocate(int num_samples, int n, const std::vector<std::string>& joint_names) {
  if (!joint_names.empty() && static_cast<int>(joint_names.size()) != n) {
    throw std::invalid_argument("joint simulation: " + std::to_string(joint_names.size()) + " joint names for " +
                                std::to_string(n) + " joints");
  }
  JointSamples out;
  out.joint_names = joint_names;
  out.t.resize(num_samples);
  out.q.resize(num_samples, n);
  out.qd.resize(num_samples, n);
  out.qdd.resize(num_samples, n);
  out.tau.resize(num_samples, n);
  return out;
}

void CheckPoint(const JointTrajectoryPoint& p, int n, double t) {
  if (p.q.size() != n || p.qd.size() != n || p.qdd.size() != n) {
    throw std::invalid_argument("reference at t = " + FormatNumber(t, kMessageDigits) + " s has sizes " + std::to_string(p.q.size()) + ", " +
                                std::to_string(p.qd.size()) + ", " + std::to_string(p.qdd.size()) + " for " +
                                std::to_string(n) + " joints");
  }
  if (!p.q.allFinite() || !p.qd.allFinite() || !p.qdd.allFinite()) {
    throw std::invalid_argument("reference at t = " + FormatNumber(t, kMessageDigits) + " s is not finite");
  }
}

Eigen::VectorXd Broadcast(const Eigen::VectorXd& gain, int n, const char* name) {
  if (gain.size() != 1 && gain.size() != n) {
    throw std::invalid_argument(std::string("joint simulation: ") + name + " must have 1 or " + std::to_string(n) +
                                " entries, got " + std::to_string(gain.size()));
  }
  if (!gain.allFinite() || (gain.array() < 0.0).any()) {
    throw std::invalid_argument(std::string("joint simulation: ") + name + " must be finite and >= 0");
  }
  return gain.size() == 1 ? Eigen::VectorXd::Constant(n, gain[0]) : gain;
}

// Zero-mean unit normal draws by Box-Muller from std::mt19937_64 (the same on every library).
class NormalSource {
 public:
  explicit NormalSource(std::uint64_t seed) : gen_(seed) {}
  double operator()() {
    if (has_spare_) {
      has_spare_ = false;
      return spare_;
    }
    const double u1 = (static_cast<double>(gen_() >> 11) + 1.0) * 0x1.0p-53;  // (0, 1]
    const double u2 = static_cast<double>(gen_() >> 11) * 0x1.0p-53;          // [0, 1)
    const double r = std::sqrt(-2.0 * std::log(u1));
    spare_ = r * std::sin(kTwoPi * u2);
    has_spare_ = true;
    return r * std::cos(kTwoPi * u2);
  }

 private:
  std::mt19937_64 gen_;
  double spare_ = 0.0;
  bool has_spare_ = false;
};

void AddNoise(double sigma, const char* name, NormalSource& normal, Eigen::MatrixXd* m) {
  if (!std::isfinite(sigma) || sigma < 0.0) {
    throw std::invalid_argument(std::string("noise: standard deviation of ") + name + " must be finite and >= 0, got " +
                                FormatNumber(sigma, kMessageDigits));
  }
  for (Eigen::Index k = 0; k < m->size(); ++k) m->data()[k] += sigma * normal();
}

}  // namespace

namespace {

// The plant's bias and mass matrix at (q, qd), factored, or what is wrong with them.
struct PlantAt {
  Eigen::VectorXd bias;  // id(q, qd, 0)
  Eigen::LLT<Eigen::MatrixXd> mass;
  enum class Failure { kNone, kNonFinite, kNotPositiveDefinite } failure = Failure::kNone;
};

PlantAt EvaluatePlant(const JointDynamicsFn& id, const Eigen::VectorXd& q, const Eigen::VectorXd& qd) {
  const Eigen::Index n = q.size();
  PlantAt p;
  Eigen::VectorXd e = Eigen::VectorXd::Zero(n);
  p.bias = id(q, qd, e);
  if (p.bias.size() != n) {
    throw std::invalid_argument("forward dynamics: inverse dynamics returned " + std::to_string(p.bias.size()) +
                                " torques for " + std::to_string(n) + " joints");
  }
  Eigen::MatrixXd M(n, n);
  for (Eigen::Index k = 0; k < n; ++k) {
    e[k] = 1.0;
    const Eigen::VectorXd column = id(q, qd, e);
    if (column.size() != n) {
      throw std::invalid_argument("forward dynamics: inverse dynamics returned " + std::to_string(column.size()) +
                                  " torques for " + std::to_string(n) + " joints");
    }
    M.col(k) = column - p.bias;
    e[k] = 0.0;
  }
  if (!p.bias.allFinite() || !M.allFinite()) {
    p.failure = PlantAt::Failure::kNonFinite;
    return p;
  }
  p.mass.compute(0.5 * (M + M.transpose()));
  if (p.mass.info() != Eigen::Success) p.failure = PlantAt::Failure::kNotPositiveDefinite;
  return p;
}

constexpr const char* kNonFiniteText = "inverse dynamics returned non-finite values at this state";
constexpr const char* kNotPositiveDefiniteText =
    "the mass matrix (qdd coefficient of the inverse dynamics) is not positive definite";

}  // namespace

Eigen::VectorXd ForwardDynamics(const JointDynamicsFn& id, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                                const Eigen::VectorXd& tau) {
  const Eigen::Index n = q.size();
  if (qd.size() != n || tau.size() != n) {
    throw std::invalid_argument("forward dynamics: q, qd, tau have sizes " + std::to_string(n) + ", " +
                                std::to_string(qd.size()) + ", " + std::to_string(tau.size()));
  }
  const PlantAt p = EvaluatePlant(id, q, qd);
  if (p.failure == PlantAt::Failure::kNonFinite) {
    throw std::invalid_argument(std::string("forward dynamics: ") + kNonFiniteText);
  }
  if (p.failure == PlantAt::Failure::kNotPositiveDefinite) {
    throw std::invalid_argument(std::string("forward dynamics: ") + kNotPositiveDefiniteText);
  }
  return p.mass.solve(tau - p.bias);
}

SimulationDiverged::SimulationDiverged(double time, const std::string& reason)
    : std::invalid_argument("the simulation diverged at t = " + FormatNumber(time, kMessageDigits) + " s (" + reason + ")"),
      time_(time),
      reason_(reason) {}

namespace {

// Where the state is: the size of q and qd, for the reason of a divergence.
std::string StateText(const Eigen::VectorXd& q, const Eigen::VectorXd& qd) {
  return "max |q| = " + FormatNumber(q.cwiseAbs().maxCoeff(), kMessageDigits) + ", max |qd| = " + FormatNumber(qd.cwiseAbs().maxCoeff(), kMessageDigits);
}

// The initial state: q and qd of one size >= 1, finite.
void CheckInitialState(const Eigen::VectorXd& q_start, const Eigen::VectorXd& qd_start) {
  const Eigen::Index n = q_start.size();
  if (n < 1 || qd_start.size() != n) {
    throw std::invalid_argument("joint simulation: initial q and qd have sizes " + std::to_string(n) + " and " +
                                std::to_string(qd_start.size()) + " (need equal and >= 1)");
  }
  if (!q_start.allFinite() || !qd_start.allFinite()) {
    throw std::invalid_argument("joint simulation: initial state is not finite");
  }
}

// The RK4 steps of the interval starting at t, from the loop's fastest rate rho there, counted in
// st; SimulationDiverged if more would be needed than the shortest step allows.
int StepsOfInterval(double rho, const Timing& timing, double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                    JointSimulationStats& st) {
  const double needed = StepsPerSample(timing.sample_period, rho, timing.steps_per_sample);
  const double most = MaxStepsPerSample(timing.sample_period);
  if (!(needed <= most)) {
    throw SimulationDiverged(
        t, std::isfinite(rho)
               ? "the loop's fastest mode is " + FormatNumber(rho, kMessageDigits) + " 1/s: RK4 would need " + FormatNumber(needed, kMessageDigits) +
                     " steps per sample of " + FormatNumber(timing.sample_period, kMessageDigits) + " s, more than the " + FormatNumber(most, kMessageDigits) +
                     " of the shortest step " + FormatNumber(kShortestStep, kMessageDigits) + " s; " + StateText(q, qd)
               : "the loop's Jacobian is non-finite: the plant or the command is not finite beside the "
                 "state reached, " + StateText(q, qd));
  }
  const int steps = static_cast<int>(needed);
  if (rho > st.max_rate) {
    st.max_rate = rho;
    st.max_rate_time = t;
  }
  st.min_steps_per_sample = st.min_steps_per_sample == 0 ? steps : std::min(st.min_steps_per_sample, steps);
  st.max_steps_per_sample = std::max(st.max_steps_per_sample, steps);
  st.total_steps += steps;
  return steps;
}

// One classical RK4 step of length h on (q, qd) with tau held, from qdd = forward(q, qd, tau):
// k1 = (qd, qdd). SimulationDiverged (at t) if the state becomes non-finite.
template <typename Forward>
void Rk4Step(const Forward& forward, const Eigen::VectorXd& tau, const Eigen::VectorXd& qdd, double h, double t,
             Eigen::VectorXd& q, Eigen::VectorXd& qd) {
  const Eigen::VectorXd v2 = qd + 0.5 * h * qdd;
  const Eigen::VectorXd a2 = forward(q + 0.5 * h * qd, v2, tau);
  const Eigen::VectorXd v3 = qd + 0.5 * h * a2;
  const Eigen::VectorXd a3 = forward(q + 0.5 * h * v2, v3, tau);
  const Eigen::VectorXd v4 = qd + h * a3;
  const Eigen::VectorXd a4 = forward(q + h * v3, v4, tau);
  q += (h / 6.0) * (qd + 2.0 * v2 + 2.0 * v3 + v4);
  qd += (h / 6.0) * (qdd + 2.0 * a2 + 2.0 * a3 + a4);
  if (!q.allFinite() || !qd.allFinite()) {
    throw SimulationDiverged(t, "the state (q, qd) became non-finite in a step of " + FormatNumber(h, kMessageDigits) + " s");
  }
}

JointSamples Integrate(const JointDynamicsFn& plant, const JointControllerFn& controller,
                       const Eigen::VectorXd& q_start, const Eigen::VectorXd& qd_start,
                       const JointSimulationOptions& options, const std::vector<std::string>& joint_names,
                       JointSimulationStats* stats) {
  const int n = static_cast<int>(q_start.size());
  CheckInitialState(q_start, qd_start);
  const Timing timing = CheckTiming(options, true);
  JointSamples out = Allocate(timing.num_samples, n, joint_names);
  JointSimulationStats local_stats;
  JointSimulationStats& st = stats != nullptr ? *stats : local_stats;
  st = JointSimulationStats();
  st.max_rate_time = options.start_time;

  auto command = [&](double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd) {
    Eigen::VectorXd tau = controller(t, q, qd);
    if (tau.size() != n) {
      throw std::invalid_argument("controller returned " + std::to_string(tau.size()) + " torques for " +
                                  std::to_string(n) + " joints");
    }
    if (!tau.allFinite()) throw std::invalid_argument("torque command is not finite");
    return tau;
  };

  double t = options.start_time;
  bool initial = true;  // the first evaluation, at the initial state: failures there are the model's
  // The plant at (q, qd): a failure at the initial state is a model error, past it a divergence.
  auto plant_at = [&](const Eigen::VectorXd& q, const Eigen::VectorXd& qd) {
    PlantAt p = EvaluatePlant(plant, q, qd);
    if (p.failure != PlantAt::Failure::kNone) {
      const char* what = p.failure == PlantAt::Failure::kNonFinite ? kNonFiniteText : kNotPositiveDefiniteText;
      if (initial) {
        throw std::invalid_argument(std::string("the model: ") + what +
                                    " at the initial state (a model error, not a diverged simulation)");
      }
      throw SimulationDiverged(t, std::string(what) + " at the state reached, " + StateText(q, qd));
    }
    return p;
  };
  auto forward = [&](const Eigen::VectorXd& q, const Eigen::VectorXd& qd, const Eigen::VectorXd& tau) {
    const PlantAt p = plant_at(q, qd);
    return Eigen::VectorXd(p.mass.solve(tau - p.bias));
  };

  Eigen::VectorXd q = q_start, qd = qd_start;
  try {
    for (int i = 0; i < timing.num_samples; ++i) {
      const double t_i = options.start_time + i * timing.sample_period;
      t = t_i;
      Eigen::VectorXd tau = command(t, q, qd);
      const PlantAt at_sample = plant_at(q, qd);
      initial = false;
      Eigen::VectorXd qdd = at_sample.mass.solve(tau - at_sample.bias);
      out.t[i] = t_i;
      out.q.row(i) = q.transpose();
      out.qd.row(i) = qd.transpose();
      out.qdd.row(i) = qdd.transpose();
      out.tau.row(i) = tau.transpose();
      if (options.progress) options.progress(static_cast<double>(i + 1) / timing.num_samples);
      if (i + 1 == timing.num_samples) break;

      // The steps of this interval from the loop's rate here (the sample's own mass matrix).
      const double rho = StepRate(at_sample.mass, DifferencedPlantSlopes(plant, q, qd, qdd),
                                  DifferencedCommandSlopes(controller, t, q, qd, tau));
      const int steps = StepsOfInterval(rho, timing, t, q, qd, st);
      const double h = timing.sample_period / steps;

      for (int s = 0; s < steps; ++s) {
        if (s > 0) {
          t = t_i + s * h;
          tau = command(t, q, qd);
          qdd = forward(q, qd, tau);
        }
        Rk4Step(forward, tau, qdd, h, t, q, qd);
      }
    }
  } catch (const SimulationDiverged&) {
    throw;
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument("joint simulation at t = " + FormatNumber(t, kMessageDigits) + " s: " + e.what());
  }
  return out;
}

}  // namespace

JointSamples SimulateJoints(const JointDynamicsFn& plant, const JointControllerFn& controller,
                            const Eigen::VectorXd& q_start, const Eigen::VectorXd& qd_start,
                            const JointSimulationOptions& options, const std::vector<std::string>& joint_names,
                            JointSimulationStats* stats) {
  return Integrate(plant, controller, q_start, qd_start, options, joint_names, stats);
}

JointSamples SimulateTracking(const JointDynamicsFn& plant, const JointDynamicsFn& nominal,
                              const JointReferenceFn& reference, const JointSimulationOptions& options,
                              const std::vector<std::string>& joint_names, JointSimulationStats* stats) {
  CheckTiming(options, true);  // option errors before anything is evaluated
  const JointTrajectoryPoint start = reference(options.start_time);
  const int n = static_cast<int>(start.q.size());
  if (n < 1) throw std::invalid_argument("joint simulation: the reference has no joints");
  CheckPoint(start, n, options.start_time);
  const Eigen::VectorXd kp = Broadcast(options.kp, n, "kp");
  const Eigen::VectorXd kd = Broadcast(options.kd, n, "kd");
  // The reference of the last time asked for: the rate's differences ask 2n times at one time.
  double ref_time = std::numeric_limits<double>::quiet_NaN();
  JointTrajectoryPoint ref;
  auto controller = [&](double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd) -> Eigen::VectorXd {
    if (!(t == ref_time)) {
      ref = reference(t);
      CheckPoint(ref, n, t);
      ref_time = t;
    }
    const Eigen::VectorXd tau =
        nominal(q, qd, ref.qdd + kp.cwiseProduct(ref.q - q) + kd.cwiseProduct(ref.qd - qd));
    if (tau.size() != n) {
      throw std::invalid_argument("nominal model returned " + std::to_string(tau.size()) + " torques for " +
                                  std::to_string(n) + " joints");
    }
    return tau;
  };
  return Integrate(plant, controller, start.q, start.qd, options, joint_names, stats);
}

JointSamples SampleTrajectory(const JointDynamicsFn& id, const JointReferenceFn& reference,
                              const JointSimulationOptions& options, const std::vector<std::string>& joint_names) {
  const Timing timing = CheckTiming(options, false);
  const JointTrajectoryPoint first = reference(options.start_time);
  const int n = static_cast<int>(first.q.size());
  if (n < 1) throw std::invalid_argument("sample trajectory: the reference has no joints");
  JointSamples out = Allocate(timing.num_samples, n, joint_names);
  for (int i = 0; i < timing.num_samples; ++i) {
    const double t = options.start_time + i * timing.sample_period;
    const JointTrajectoryPoint p = i == 0 ? first : reference(t);
    CheckPoint(p, n, t);
    const Eigen::VectorXd tau = id(p.q, p.qd, p.qdd);
    if (tau.size() != n) {
      throw std::invalid_argument("sample trajectory: inverse dynamics returned " + std::to_string(tau.size()) +
                                  " torques for " + std::to_string(n) + " joints");
    }
    out.t[i] = t;
    out.q.row(i) = p.q.transpose();
    out.qd.row(i) = p.qd.transpose();
    out.qdd.row(i) = p.qdd.transpose();
    out.tau.row(i) = tau.transpose();
  }
  return out;
}

JointSamples AddGaussianNoise(const JointSamples& samples, const SampleNoise& sigma, std::uint64_t seed) {
  JointSamples out = samples;
  NormalSource normal(seed);
  AddNoise(sigma.q, "q", normal, &out.q);
  AddNoise(sigma.qd, "qd", normal, &out.qd);
  AddNoise(sigma.qdd, "qdd", normal, &out.qdd);
  AddNoise(sigma.tau, "tau", normal, &out.tau);
  return out;
}

}  // namespace inertial
