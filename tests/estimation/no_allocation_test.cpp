// The online estimators allocate nothing per sample. Proven two ways around long runs of
// updates: Eigen's EIGEN_RUNTIME_NO_MALLOC guard (this program compiles the core sources that the
// estimators' Update runs itself, with the guard on and assertions live; tests/CMakeLists.txt says
// which and how they were found), and a counting malloc / operator new hook that sees every heap
// allocation of the process, any file's and the standard library's too.
// Robots are built in code (a 3-DOF leg with rotors and friction, a 7-DOF arm with friction and
// offsets, one body) so that the core alone is linked.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <new>

#include "inertial/estimation/online/online_body_estimator.hpp"
#include "inertial/estimation/online/online_joint_estimator.hpp"
#include "inertial/inertia/closed_form_bodies.hpp"
#include "inertial/model/fourier_trajectory.hpp"
#include "inertial/model/rigid_body_regressor.hpp"

#ifdef INERTIAL_TEST_UNDER_ASAN
// AddressSanitizer replaces malloc itself, and a second replacement cannot coexist with it: the
// tests report themselves skipped (tests/CMakeLists.txt builds this file without the guard there).
#define INERTIAL_SKIP_UNDER_ASAN() \
  GTEST_SKIP() << "this test replaces malloc to count allocations, which AddressSanitizer owns; the normal build runs it"
#else
#define INERTIAL_SKIP_UNDER_ASAN() (void)0
#ifndef EIGEN_RUNTIME_NO_MALLOC
#error "this test must be compiled with EIGEN_RUNTIME_NO_MALLOC"
#endif
#ifdef NDEBUG
#error "this test needs assertions (Eigen's guard is an assertion)"
#endif

#endif

#include "allocation_counter.hpp"

namespace inertial {
namespace {

// Counts heap allocations and arms Eigen's guard around `body`.
template <typename F>
long AllocationsDuring(F&& body) {
  g_allocations = 0;
#ifndef INERTIAL_TEST_UNDER_ASAN
  Eigen::internal::set_is_malloc_allowed(false);
#endif
  g_counting = true;
  body();
  g_counting = false;
#ifndef INERTIAL_TEST_UNDER_ASAN
  Eigen::internal::set_is_malloc_allowed(true);
#endif
  return g_allocations;
}

JointModel Joint(const std::string& name, const Vector3& p, const Vector3& axis) {
  JointModel j;
  j.name = name;
  j.p_parent_joint = p;
  j.axis = axis.normalized();
  return j;
}

RobotDynamics Leg() {
  KinematicTree tree;
  tree.AddBody("abad_link", -1, Joint("abad", Vector3(0, 0, 0), Vector3::UnitX()), SolidBox(2.0, 0.1, 0.1, 0.1));
  tree.AddBody("thigh", 0, Joint("hip", Vector3(0, 0.06, 0), Vector3::UnitY()),
               SolidBox(1.8, 0.05, 0.05, 0.34, Pose{Matrix3::Identity(), Vector3(0, 0, -0.17)}));
  tree.AddBody("shank", 1, Joint("knee", Vector3(0, 0, -0.34), Vector3::UnitY()),
               SolidBox(0.45, 0.03, 0.03, 0.34, Pose{Matrix3::Identity(), Vector3(0, 0, -0.17)}));
  return RobotDynamics(tree, {"abad", "hip", "knee"},
                       ParseEffectList("viscous,coulomb,rotor@abad:gear=6,rotor@hip:gear=6,rotor@knee:gear=9"), nullptr);
}

RobotDynamics Arm() {
  KinematicTree tree;
  std::vector<std::string> names;
  for (int i = 0; i < 7; ++i) {
    names.push_back("joint" + std::to_string(i + 1));
    const Vector3 axis = i % 2 == 0 ? Vector3::UnitZ() : Vector3::UnitY();
    tree.AddBody("link" + std::to_string(i + 1), i - 1, Joint(names.back(), Vector3(0, 0, i == 0 ? 0.1 : 0.2), axis),
                 SolidCylinder(4.0 - 0.5 * i, 0.06, 0.2, Pose{Matrix3::Identity(), Vector3(0, 0.01, 0.1)}));
  }
  return RobotDynamics(tree, names, ParseEffectList("viscous,coulomb,offset"), nullptr);
}

JointSample SampleAt(const RobotDynamics& model, const Eigen::VectorXd& x_true, int k) {
  const JointTrajectoryPoint p = RandomFourierTrajectory(model.num_dofs(), 4, 0.3, 0.7, 9).Evaluate(1e-3 * k);
  JointSample s{1e-3 * k, p.q, p.qd, p.qdd, model.InverseDynamics(x_true, p.q, p.qd, p.qdd)};
  if (k % 500 == 250) s.tau[0] += 1000.0;                        // an outlier
  if (k % 700 == 350) s.qd[1] = std::numeric_limits<double>::quiet_NaN();  // a broken sample
  if (k % 900 == 450) s.t -= 1.0;                                // time going backwards
  return s;
}

TEST(NoAllocation, TheHookAndTheGuardSeeAllocations) {
  INERTIAL_SKIP_UNDER_ASAN();
  // The counting hook can fail: a vector allocates.
  g_allocations = 0;
  g_counting = true;
  { std::vector<double> v(100); }
  g_counting = false;
  EXPECT_GT(g_allocations, 0);
  // Eigen's guard can fail: a dynamic matrix aborts the process.
  EXPECT_DEATH(AllocationsDuring([] { Eigen::MatrixXd m(10, 10); m.setZero(); }), "");
}

// Every estimator over a stream with an outlier, a broken sample, time going backwards and a
// sample of the wrong size: not one allocation.
// without_qdd: the samples' qdd is not measured (but at every 1000th), so the momentum rows run,
// and restart after each sample with qdd.
void ExpectNoAllocation(const RobotDynamics& model, int num_samples, double min_accepted_fraction, bool without_qdd = false) {
  Eigen::VectorXd x_true = Eigen::VectorXd::Constant(model.num_parameters(), 0.1);
  std::vector<JointSample> samples;
  for (int k = 0; k < num_samples; ++k) {
    samples.push_back(SampleAt(model, x_true, k));
    samples.back().qdd_measured = !without_qdd || k % 1000 == 500;
  }
  for (EstimatorKind kind :
       {EstimatorKind::kGaussNewton, EstimatorKind::kEkf, EstimatorKind::kGradient, EstimatorKind::kLinearRls}) {
    OnlineEstimatorOptions o;
    o.kind = kind;
    o.kalman.forgetting = 0.999;
    o.kalman.process_noise = 1e-8;
    o.fit.forgetting_time = 20.0;  // the forgetting pass of the rank update runs too
    OnlineJointEstimator est(model, Eigen::VectorXd::Zero(model.num_parameters()), o);
    JointSample wrong = samples[0];
    wrong.tau.resize(model.num_dofs() + 1);  // made outside the guarded region
    // The online fit's solve (it allocates; off the tick, as inertiald's solver thread) after its
    // warm-up and then between runs of 250 ticks, so that the ticks run the gate with a solve's
    // noise and covariance, and the refused samples are judged as they are in use (a fit that is
    // never solved again refuses what its first estimate mispredicts: online_fit.hpp).
    size_t first = 0;
    if (kind == EstimatorKind::kGaussNewton) {
      for (; first < 64; ++first) est.Update(samples[first]);
      ASSERT_TRUE(est.Solve());
    }
    const size_t run = kind == EstimatorKind::kGaussNewton ? 250 : samples.size();
    long allocations = 0;
    for (size_t begin = first; begin < samples.size(); begin += run) {
      allocations += AllocationsDuring([&] {
        for (size_t k = begin; k < std::min(samples.size(), begin + run); ++k) est.Update(samples[k]);
      });
      if (est.SolveDue()) est.Solve();
    }
    allocations += AllocationsDuring([&] { est.Update(wrong); });
    EXPECT_EQ(allocations, 0) << ToString(kind) << " on " << model.num_dofs() << " DOFs";
    const UpdateCounters& c = est.estimator().counters();
    EXPECT_GT(c.accepted(), min_accepted_fraction * num_samples) << ToString(kind) << ": " << c[UpdateStatus::kOutlier] << " outliers";
    EXPECT_GT(c[UpdateStatus::kNonFinite], 0u);
    EXPECT_GT(c[UpdateStatus::kOutOfOrder], 0u);
    EXPECT_EQ(c[UpdateStatus::kWrongSize], 1u);
  }
}

TEST(NoAllocation, JointEstimatorsOnALegAndAnArm) {
  INERTIAL_SKIP_UNDER_ASAN();
  for (const RobotDynamics& model : {Leg(), Arm()}) {
    ExpectNoAllocation(model, 5000, 0.8);
    ExpectNoAllocation(model, 5000, 0.8, true);  // rows without qdd (momentum_rows.hpp)
  }
}

// A humanoid's size: 24 joints, 312 parameters, so the large-P paths (blocked SYRK downdate, the
// span products over long spans, the triangular solve for W) run too.
TEST(NoAllocation, JointEstimatorsOnALongChain) {
  INERTIAL_SKIP_UNDER_ASAN();
  KinematicTree tree;
  std::vector<std::string> names;
  for (int i = 0; i < 24; ++i) {
    names.push_back("joint" + std::to_string(i + 1));
    const Vector3 axis = i % 2 == 0 ? Vector3::UnitY() : Vector3::UnitX();
    tree.AddBody("link" + std::to_string(i + 1), i - 1, Joint(names.back(), Vector3(0, 0, 0.08), axis),
                 SolidCylinder(2.0 * std::pow(0.95, i), 0.03, 0.08, Pose{Matrix3::Identity(), Vector3(0, 0.005, 0.04)}));
  }
  // The gradient law, 0.1 off in all 312 parameters, needs longer than these 1000 samples to bring
  // its innovations inside the gate (it rejects about 450): half accepted shows the update ran.
  ExpectNoAllocation(RobotDynamics(tree, names, ParseEffectList("viscous,offset"), nullptr), 1000, 0.5);
}

TEST(NoAllocation, SingleBodyEstimators) {
  INERTIAL_SKIP_UNDER_ASAN();
  const InertialParams truth = SolidBox(1.3, 0.2, 0.1, 0.05, Pose{Matrix3::Identity(), Vector3(0.05, 0, 0.02)});
  std::vector<BodySample> samples;
  for (int k = 0; k < 5000; ++k) {
    BodySample s;
    s.t = 1e-3 * k;
    for (int i = 0; i < 6; ++i) {
      s.twist[i] = std::sin(2 * M_PI * (0.3 + 0.2 * i) * s.t + i);
      s.acceleration[i] = 2 * M_PI * (0.3 + 0.2 * i) * std::cos(2 * M_PI * (0.3 + 0.2 * i) * s.t + i);
    }
    s.has_acceleration = k % 2 == 0;  // both forms, and pairs across them
    s.gravity = Vector3(0, 0, -9.81);
    s.wrench = RigidBodyRegressor(s.twist, s.acceleration, s.gravity) * truth.vector();
    samples.push_back(s);
  }
  for (EstimatorKind kind : {EstimatorKind::kGaussNewton, EstimatorKind::kGradient, EstimatorKind::kLinearRls}) {
    OnlineEstimatorOptions o;
    o.kind = kind;
    OnlineBodyEstimator est(SolidSphere(1.0, 0.05), o);
    const long allocations = AllocationsDuring([&] {
      for (const BodySample& s : samples) est.Update(s);
    });
    EXPECT_EQ(allocations, 0) << ToString(kind);
    EXPECT_GT(est.estimator().counters().accepted(), 4000u);
  }
}

}  // namespace
}  // namespace inertial
