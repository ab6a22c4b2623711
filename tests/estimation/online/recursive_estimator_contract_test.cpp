// The contract of recursive_estimator_contract.hpp, run for every online estimator: on a robot
// (OnlineJointEstimator: the online fit "gauss_newton", the extended Kalman filter "ekf", the
// gradient law, linear RLS) and on one body (OnlineBodyEstimator: Gauss-Newton, the same filter at
// fixed sizes; the gradient law; linear RLS). The worlds are simulated once, seeded: the leg chain
// (leg_chain.hpp) with viscous friction tracking a Fourier excitation (simulated_robot.hpp), and a
// box on a force/torque sensor (body_stream.hpp), half its samples with the twist's derivative and
// half without (paired by the midpoint rule), both with Gaussian measurement noise.
#include "estimation/online/recursive_estimator_contract.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "estimation/body_stream.hpp"
#include "estimation/leg_chain.hpp"
#include "inertial/model/rigid_body_regressor.hpp"
#include "simulated_robot.hpp"

namespace inertial::testing {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// ---------------------------------------------------------------------------------------------
// The robot: the leg (3 DOFs, 3 links, viscous friction), links up to +-40 % off the priors in
// mass (TrueParameters, spread 0.25), friction 0.5 N m s. 12 s at 100 Hz of training, torque
// noise 0.05 N m; held out: 12 s of another trajectory, its noise-free torques.

constexpr double kRobotSigma = 0.05;

// The convergence bound, from the simulator's noise sigma. Least squares (the online fit, the
// filters, linear RLS) of F coefficients from R rows of noise sigma predicts data like its own with
// an RMS error of sigma sqrt(F / R) (the trace of the hat matrix over R); the held-out trajectory
// excites the coefficients differently, and the estimate carries its prior's pull, so 5 times that
// is allowed: still a tenth of the noise (0.024 N m on the leg, 0.009 on the body) and 1 % of the
// priors' errors. The gradient law minimizes the same objective (gradient_estimator.hpp) and is
// held to the same bound.
double Bound(EstimatorKind, double sigma, int features, double rows) { return 5.0 * sigma * std::sqrt(features / rows); }

struct RobotWorld {
  RobotDynamics model;
  Eigen::VectorXd x_true;
  std::vector<JointSample> train;
  JointSamples held_out;  // noise-free
};

const RobotWorld& Leg() {
  static const RobotWorld world = [] {
    RobotWorld w{RobotDynamics(LegChain(LegPriorLinks()), kLegJoints, ParseEffectList("viscous"), NoLinks()), {}, {}, {}};
    w.x_true = TrueParameters(w.model, {0.5}, 37, 0.25);
    const SimulatedLogs logs = SimulateLogs(w.model, w.x_true, kRobotSigma, 12.0, 37, 100);
    w.train.resize(logs.train.size());
    for (int i = 0; i < logs.train.size(); ++i) CopySample(logs.train, i, &w.train[i]);
    w.held_out = logs.test_clean;
    return w;
  }();
  return world;
}

double RobotHeldOutRms(const Eigen::VectorXd& w) {
  const RobotWorld& world = Leg();
  const JointSamples& log = world.held_out;
  double s = 0.0;
  for (int i = 0; i < log.size(); ++i) {
    const Eigen::VectorXd tau = world.model.InverseDynamicsFromCoefficients(
        w, log.q.row(i).transpose(), log.qd.row(i).transpose(), log.qdd.row(i).transpose());
    s += (tau - log.tau.row(i).transpose()).squaredNorm();
  }
  return std::sqrt(s / (log.size() * log.tau.cols()));
}

// The refusals of time order every estimator shares: the last time repeated, a time before it.
template <typename Sample>
void AppendTimeOrderRefusals(const Sample& next, const Sample& last, std::vector<Refusal<Sample>>& out) {
  Sample s = next;
  s.t = last.t;
  out.push_back({s, UpdateStatus::kOutOfOrder, "the last time repeated"});
  s.t = last.t - 0.5;
  out.push_back({s, UpdateStatus::kOutOfOrder, "a time before the last"});
}

template <EstimatorKind K>
struct RobotTraits {
  using Estimator = OnlineJointEstimator;
  using Sample = JointSample;
  static constexpr bool kConsistent = K != EstimatorKind::kLinearRls;
  static constexpr bool kRestoreIsComplete = K != EstimatorKind::kGaussNewton;
  static constexpr int kConvergencePasses = 1;
  static constexpr bool kReachesTheFloorInTheseSamples = true;
  // A robot sample has no held half of a pair.
  static std::string Name() { return "robot " + std::string(ToString(K)); }
  static OnlineEstimatorOptions Options() {
    OnlineEstimatorOptions o;
    o.kind = K;
    o.measurement_sigma = kRobotSigma;  // the estimators are told the noise; the rest are defaults
    // The gradient law gates on the residual over sigma, and has no covariance to know that the
    // prior's residuals (2 N m RMS here, 40 noise sigmas) are model error: told the noise, it refuses
    // nearly every sample until its change detector forces 1 in 51 through. Its sigma is the size
    // of the residuals it is to take (as online_joint_estimator_test.cpp runs it).
    if (K == EstimatorKind::kGradient) o.measurement_sigma = 1.0;
    return o;
  }
  static std::unique_ptr<Estimator> Make() {
    return std::make_unique<Estimator>(Leg().model, Eigen::VectorXd::Zero(Leg().model.num_parameters()), Options());
  }
  static const std::vector<Sample>& Train() { return Leg().train; }
  static UpdateStatus Update(Estimator& e, const Sample& s) { return e.Update(s); }
  static void OffTick(Estimator& e) {
    if (e.SolveDue()) e.Solve();
  }
  static void Finish(Estimator& e) { e.Solve(); }
  static const RecursiveEstimator& Core(const Estimator& e) { return e.estimator(); }
  static bool Restore(Estimator& e, const EstimatorState& s, std::string* why) { return e.Restore(s, why); }
  static int NumBodies() { return static_cast<int>(Leg().model.bodies().size()); }
  static InertialParams Body(const Estimator& e, int b) { return e.Body(b); }
  static Eigen::VectorXd Coefficients(const Estimator& e) { return e.coefficients(); }
  static Sample Outlier(Sample s, double factor) {
    s.tau[1] += factor * kRobotSigma;
    return s;
  }
  static std::vector<Refusal<Sample>> Refusals(const Sample& next, const Sample& last) {
    std::vector<Refusal<Sample>> out;
    const int n = static_cast<int>(next.q.size());
    const char* names[4] = {"q", "qd", "qdd", "tau"};
    for (int f = 0; f < 4; ++f) {
      for (double bad : {kNaN, kInf, -kInf}) {
        Sample s = next;
        Eigen::VectorXd* v[4] = {&s.q, &s.qd, &s.qdd, &s.tau};
        (*v[f])[(f + out.size()) % n] = bad;
        out.push_back({s, UpdateStatus::kNonFinite, std::string(names[f]) + " = " + std::to_string(bad)});
      }
      Sample s = next;
      Eigen::VectorXd* v[4] = {&s.q, &s.qd, &s.qdd, &s.tau};
      v[f]->conservativeResize(f % 2 == 0 ? n + 1 : n - 1);
      v[f]->setConstant(0.1);
      out.push_back({s, UpdateStatus::kWrongSize, std::string("wrong size of ") + names[f]});
    }
    for (double t : {kNaN, kInf, -kInf}) {
      Sample s = next;
      s.t = t;
      out.push_back({s, UpdateStatus::kNonFinite, "t = " + std::to_string(t)});
    }
    AppendTimeOrderRefusals(next, last, out);
    return out;
  }
  static double HeldOutRms(const Estimator& e) { return RobotHeldOutRms(e.coefficients()); }
  static double PriorHeldOutRms() { return RobotHeldOutRms(Leg().model.Coefficients(Eigen::VectorXd::Zero(Leg().model.num_parameters()))); }
  static double ConvergenceBound() { return Bound(K, kRobotSigma, Leg().model.num_features(), 3.0 * Leg().train.size()); }
};

// ---------------------------------------------------------------------------------------------
// The body: a 1.3 kg box 8 cm off the sensor frame (body_stream.hpp), from a 1 kg sphere at the
// origin. 12 s at 100 Hz, wrench noise 0.05 N and N m, every other sample without its twist's
// derivative (paired with the previous such sample by the midpoint rule).

constexpr double kBodySigma = 0.05;

struct BodyWorld {
  std::vector<BodySample> train;
  std::vector<BodySample> held_out;  // noise-free, with accelerations
};

const BodyWorld& Box() {
  static const BodyWorld world = [] {
    BodyWorld w;
    w.train = Stream(TrueBody(), 12.0, 100.0, kBodySigma, 41);
    for (size_t k = 0; k < w.train.size(); ++k) w.train[k].has_acceleration = k % 2 == 0;
    w.held_out = Stream(TrueBody(), 6.0, 50.0, 0.0, 43, 100.0);
    return w;
  }();
  return world;
}

double BodyHeldOutRms(const InertialParams& body) {
  double s = 0.0;
  for (const BodySample& h : Box().held_out) {
    s += (RigidBodyRegressor(h.twist, h.acceleration, h.gravity) * body.vector() - h.wrench).squaredNorm();
  }
  return std::sqrt(s / (6.0 * Box().held_out.size()));
}

template <EstimatorKind K>
struct BodyTraits {
  using Estimator = OnlineBodyEstimator;
  using Sample = BodySample;
  static constexpr bool kConsistent = K != EstimatorKind::kLinearRls;
  // OnlineBodyEstimator::Restore drops a held twist (the first of a pair) by design: a pair never
  // spans a restore. So the original is restored too, and what is compared is that nothing else
  // survives a restore.
  static constexpr bool kRestoreIsComplete = false;
  // The gradient law takes one step per sample, each at most 10 % of the body's J (max_step), from
  // a prior far from the box (its error 140 times the bound): one pass of 1200 samples leaves it at
  // 1.25 times the bound, a second within it.
  static constexpr int kConvergencePasses = K == EstimatorKind::kGradient ? 2 : 1;
  static constexpr bool kReachesTheFloorInTheseSamples = true;
  static std::string Name() { return "body " + std::string(ToString(K)); }
  static OnlineEstimatorOptions Options() {
    OnlineEstimatorOptions o;
    o.kind = K;
    o.measurement_sigma = kBodySigma;
    o.theta_std = 1.0;  // the prior is far from the box (online_body_estimator_test.cpp)
    return o;
  }
  static std::unique_ptr<Estimator> Make() { return std::make_unique<Estimator>(Prior(), Options()); }
  static const std::vector<Sample>& Train() { return Box().train; }
  static UpdateStatus Update(Estimator& e, const Sample& s) { return e.Update(s); }
  static void OffTick(Estimator&) {}
  static void Finish(Estimator&) {}
  static const RecursiveEstimator& Core(const Estimator& e) { return e.estimator(); }
  static bool Restore(Estimator& e, const EstimatorState& s, std::string* why) { return e.Restore(s, why); }
  static int NumBodies() { return 1; }
  static InertialParams Body(const Estimator& e, int) { return e.Body(); }
  static Eigen::VectorXd Coefficients(const Estimator& e) { return e.Body().vector(); }
  static Sample Outlier(Sample s, double factor) {
    s.wrench[4] += factor * kBodySigma;
    return s;
  }
  // A body sample has fixed sizes: no wrong size can be expressed. Its acceleration is read only
  // when has_acceleration is set.
  static std::vector<Refusal<Sample>> Refusals(const Sample& next, const Sample& last) {
    std::vector<Refusal<Sample>> out;
    for (double bad : {kNaN, kInf, -kInf}) {
      const int i = static_cast<int>(out.size()) % 3;
      Sample s = next;
      s.twist[i + 3 * (out.size() % 2)] = bad;
      out.push_back({s, UpdateStatus::kNonFinite, "twist = " + std::to_string(bad)});
      s = next;
      s.wrench[5 - i] = bad;
      out.push_back({s, UpdateStatus::kNonFinite, "wrench = " + std::to_string(bad)});
      s = next;
      s.gravity[i] = bad;
      out.push_back({s, UpdateStatus::kNonFinite, "gravity = " + std::to_string(bad)});
      s = next;
      s.t = bad;
      out.push_back({s, UpdateStatus::kNonFinite, "t = " + std::to_string(bad)});
      if (next.has_acceleration) {
        s = next;
        s.acceleration[2 * i] = bad;
        out.push_back({s, UpdateStatus::kNonFinite, "acceleration = " + std::to_string(bad)});
      }
    }
    AppendTimeOrderRefusals(next, last, out);
    return out;
  }
  static double HeldOutRms(const Estimator& e) { return BodyHeldOutRms(e.Body()); }
  static double PriorHeldOutRms() { return BodyHeldOutRms(Prior()); }
  static double ConvergenceBound() { return Bound(K, kBodySigma, 10, 6.0 * Box().train.size()); }
};

using Estimators = ::testing::Types<RobotTraits<EstimatorKind::kGaussNewton>, RobotTraits<EstimatorKind::kEkf>,
                                    RobotTraits<EstimatorKind::kGradient>, RobotTraits<EstimatorKind::kLinearRls>,
                                    BodyTraits<EstimatorKind::kGaussNewton>, BodyTraits<EstimatorKind::kGradient>,
                                    BodyTraits<EstimatorKind::kLinearRls>>;

struct Names {
  template <typename T>
  static std::string GetName(int) {
    std::string name = T::Name();
    for (char& c : name) c = c == ' ' ? '_' : c;
    return name;
  }
};

}  // namespace

INSTANTIATE_TYPED_TEST_SUITE_P(All, RecursiveEstimatorContract, Estimators, Names);

// CTest registers the tests it finds in this file (gtest_add_tests, tests/CMakeLists.txt), not in
// the header that defines them; one entry per test of the contract, each running every estimator:
//   TYPED_TEST_P(RecursiveEstimatorContract, RefusalsChangeNothing)
//   TYPED_TEST_P(RecursiveEstimatorContract, NoAllocationPerTick)
//   TYPED_TEST_P(RecursiveEstimatorContract, SaveRestoreContinuesBitForBit)
//   TYPED_TEST_P(RecursiveEstimatorContract, SoundAfterEveryTick)
//   TYPED_TEST_P(RecursiveEstimatorContract, ConvergesOnASimulatedSystem)

}  // namespace inertial::testing
