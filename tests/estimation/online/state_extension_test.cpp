// A saved estimator state carried into a model with more parameters, by name: every saved entry of
// x and every entry of the covariance among saved entries lands where its name is, whatever the
// order; new entries keep the fresh state's values; new-vs-saved covariances are zero; time and
// counters are the saved ones; the result is symmetric positive definite and restores into a real
// estimator. Refusals name what differs.
#include "inertial/estimation/online/state_extension.hpp"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <random>

#include "inertial/estimation/online/online_joint_estimator.hpp"
#include "inertial/estimation/online/state_entry_names.hpp"
#include "estimation/leg_chain.hpp"
#include "test_support.hpp"

namespace inertial {
namespace {

using testing::Rng;

Eigen::MatrixXd RandomSpd(int n, Rng* rng) {
  Eigen::MatrixXd B(n, n);
  for (int i = 0; i < B.size(); ++i) B.data()[i] = rng->Normal();
  return B * B.transpose() + 0.1 * Eigen::MatrixXd::Identity(n, n);
}

EstimatorState RandomState(const std::string& kind, int n, bool with_covariance, Rng* rng) {
  EstimatorState s;
  s.kind = kind;
  s.x.resize(n);
  for (int i = 0; i < n; ++i) s.x[i] = rng->Uniform(-2, 2);
  if (with_covariance) s.P = RandomSpd(n, rng);
  return s;
}

int IndexOf(const std::vector<std::string>& names, const std::string& name) {
  return static_cast<int>(std::find(names.begin(), names.end(), name) - names.begin());
}

TEST(StateExtension, CopiesSavedEntriesByNameIntoAPermutedLargerModel) {
  Rng rng(19);
  std::mt19937 shuffle(19);
  for (int trial = 0; trial < 20; ++trial) {
    const int n_saved = 1 + trial % 7, n_new = trial % 4;
    std::vector<std::string> saved_names, fresh_names;
    for (int i = 0; i < n_saved; ++i) saved_names.push_back("old" + std::to_string(i));
    fresh_names = saved_names;
    for (int k = 0; k < n_new; ++k) fresh_names.push_back("new" + std::to_string(k));
    std::shuffle(fresh_names.begin(), fresh_names.end(), shuffle);
    EstimatorState saved = RandomState("gauss_newton", n_saved, true, &rng);
    saved.has_time = true;
    saved.last_time = rng.Uniform(0, 100);
    for (int k = 0; k < 3; ++k) saved.counters.Add(UpdateStatus::kAccepted);
    saved.counters.Add(UpdateStatus::kOutlier);
    // A fresh covariance with cross terms everywhere, so that zeroing them is seen.
    const EstimatorState fresh = RandomState("gauss_newton", n_saved + n_new, true, &rng);

    std::string why;
    const std::optional<ExtendedState> out = ExtendEstimatorState(saved, saved_names, fresh, fresh_names, &why);
    ASSERT_TRUE(out) << why;
    const EstimatorState& s = out->state;
    ASSERT_EQ(s.x.size(), n_saved + n_new);
    ASSERT_EQ(s.P.rows(), n_saved + n_new);
    for (int a = 0; a < s.x.size(); ++a) {
      const std::string& name_a = fresh_names[static_cast<size_t>(a)];
      const int i = IndexOf(saved_names, name_a);
      const bool saved_a = i < n_saved;
      EXPECT_EQ(s.x[a], saved_a ? saved.x[i] : fresh.x[a]) << name_a;
      for (int b = 0; b < s.x.size(); ++b) {
        const int j = IndexOf(saved_names, fresh_names[static_cast<size_t>(b)]);
        const bool saved_b = j < n_saved;
        const double expected = saved_a && saved_b ? saved.P(i, j) : (!saved_a && !saved_b ? fresh.P(a, b) : 0.0);
        EXPECT_EQ(s.P(a, b), expected) << name_a << ", " << fresh_names[static_cast<size_t>(b)];
      }
    }
    EXPECT_EQ(s.kind, "gauss_newton");
    EXPECT_TRUE(s.has_time);
    EXPECT_EQ(s.last_time, saved.last_time);
    EXPECT_EQ(s.counters.count, saved.counters.count);
    EXPECT_EQ(Eigen::LLT<Eigen::MatrixXd>(s.P).info(), Eigen::Success);
    // The added names: the fresh ones not saved, in the fresh order.
    std::vector<std::string> added;
    for (const std::string& f : fresh_names) {
      if (f.rfind("new", 0) == 0) added.push_back(f);
    }
    EXPECT_EQ(out->added, added);
  }
}

TEST(StateExtension, WithoutCovarianceCopiesXAlone) {
  Rng rng(3);
  const EstimatorState saved = RandomState("gradient", 3, false, &rng);
  const EstimatorState fresh = RandomState("gradient", 4, false, &rng);
  std::string why;
  const auto out = ExtendEstimatorState(saved, {"a", "b", "c"}, fresh, {"c", "d", "a", "b"}, &why);
  ASSERT_TRUE(out) << why;
  EXPECT_EQ(out->state.P.size(), 0);
  EXPECT_EQ(out->state.x, Eigen::Vector4d(saved.x[2], fresh.x[1], saved.x[0], saved.x[1]));
  EXPECT_EQ(out->added, std::vector<std::string>{"d"});
}

TEST(StateExtension, RefusesNamingWhatDiffers) {
  Rng rng(4);
  const EstimatorState saved = RandomState("gauss_newton", 3, true, &rng);
  const EstimatorState fresh = RandomState("gauss_newton", 3, true, &rng);
  const std::vector<std::string> names = {"thigh.alpha", "coulomb@knee.log_bc", "viscous@knee.log_b"};
  auto refusal = [&](const EstimatorState& s, const std::vector<std::string>& sn, const EstimatorState& f,
                     const std::vector<std::string>& fn) {
    std::string why;
    EXPECT_FALSE(ExtendEstimatorState(s, sn, f, fn, &why));
    return why;
  };
  // An effect removed: every saved parameter the model lacks is named.
  std::string why = refusal(saved, names, fresh, {"thigh.alpha", "x", "y"});
  EXPECT_NE(why.find("parameters 'coulomb@knee.log_bc', 'viscous@knee.log_b'"), std::string::npos) << why;
  EXPECT_NE(why.find("not in this model"), std::string::npos) << why;
  why = refusal(saved, names, fresh, {"thigh.alpha", "viscous@knee.log_b", "y"});
  EXPECT_NE(why.find("parameter 'coulomb@knee.log_bc' of the saved state is not in this model"), std::string::npos) << why;
  // Another estimator.
  EstimatorState gradient = fresh;
  gradient.kind = "gradient";
  gradient.P.resize(0, 0);
  why = refusal(saved, names, gradient, names);
  EXPECT_NE(why.find("'gauss_newton'"), std::string::npos) << why;
  EXPECT_NE(why.find("'gradient'"), std::string::npos) << why;
  // Names that are not one per entry, or twice.
  EXPECT_NE(refusal(saved, {"a", "b"}, fresh, names).find("3 entries but 2 names"), std::string::npos);
  EXPECT_NE(refusal(saved, {"a", "b", "a"}, fresh, {"a", "b", "c"}).find("'a' twice"), std::string::npos);
  // A covariance in one state only.
  EstimatorState no_P = saved;
  no_P.P.resize(0, 0);
  EXPECT_NE(refusal(no_P, names, fresh, names).find("covariances"), std::string::npos);
}

// With real estimators: a links-only Gauss-Newton state of the leg after some samples, carried into
// the leg with Coulomb friction on the knee and viscous friction on every joint, restores (passes
// RecursiveEstimator::Restore's checks), leaves every link's body as it was and the new effect
// coefficients at the priors.
TEST(StateExtension, ALinksOnlyStateRestoresIntoALegWithFriction) {
  for (const EstimatorKind kind : {EstimatorKind::kGaussNewton, EstimatorKind::kGradient, EstimatorKind::kLinearRls}) {
    const RobotDynamics links(testing::LegChain(testing::LegPriorLinks()), testing::kLegJoints, {}, testing::NoLinks());
    const RobotDynamics friction(testing::LegChain(testing::LegPriorLinks()), testing::kLegJoints,
                                 ParseEffectList("coulomb@knee,viscous"), testing::NoLinks());
    OnlineEstimatorOptions o;
    o.kind = kind;
    o.measurement_sigma = 0.1;
    OnlineJointEstimator before(links, Eigen::VectorXd::Zero(links.num_parameters()), o);
    const RobotDynamics truth(testing::LegChain(testing::LegTrueLinks()), testing::kLegJoints, {}, testing::NoLinks());
    Rng rng(7);
    for (int i = 0; i < 300; ++i) {
      JointSample s;
      s.t = 0.005 * i;
      s.q = Eigen::Vector3d(std::sin(s.t), 0.5 * std::cos(1.3 * s.t), 0.8 * std::sin(0.7 * s.t + 1));
      s.qd = Eigen::Vector3d(std::cos(s.t), -0.65 * std::sin(1.3 * s.t), 0.56 * std::cos(0.7 * s.t + 1));
      s.qdd = Eigen::Vector3d(-std::sin(s.t), -0.845 * std::cos(1.3 * s.t), -0.392 * std::sin(0.7 * s.t + 1));
      s.tau = truth.InverseDynamics(Eigen::VectorXd::Zero(truth.num_parameters()), s.q, s.qd, s.qdd);
      for (int k = 0; k < 3; ++k) s.tau[k] += rng.Normal(0.1);
      before.Update(s);
    }
    OnlineJointEstimator after(friction, Eigen::VectorXd::Zero(friction.num_parameters()), o);
    const EstimatorState fresh = after.estimator().State();
    std::string why;
    const auto saved_names = StateEntryNames(friction, kind, links.ParameterNames(), &why);
    const auto fresh_names = StateEntryNames(friction, kind, friction.ParameterNames(), &why);
    ASSERT_TRUE(saved_names && fresh_names) << why;
    const auto out = ExtendEstimatorState(before.estimator().State(), *saved_names, fresh, *fresh_names, &why);
    ASSERT_TRUE(out) << why;
    ASSERT_TRUE(after.estimator().Restore(out->state, &why)) << ToString(kind) << ": " << why;
    EXPECT_EQ(out->added.size(), 4u);
    // The links' coefficients w(x) (their pi) as they were, the effects' at the priors. (Through the
    // estimator: OnlineJointEstimator caches w, refreshed by its next accepted sample.)
    Eigen::VectorXd w_before(links.num_features()), w_after(friction.num_features()), w_fresh(friction.num_features());
    before.estimator().Coefficients(w_before);
    after.estimator().Coefficients(w_after);
    OnlineJointEstimator(friction, Eigen::VectorXd::Zero(friction.num_parameters()), o).estimator().Coefficients(w_fresh);
    EXPECT_EQ(w_after.head(30), w_before) << ToString(kind);
    EXPECT_EQ(w_after.tail(4), w_fresh.tail(4)) << ToString(kind);
    if (kind != EstimatorKind::kLinearRls) {
      for (int e = 0; e < 3; ++e) EXPECT_EQ(after.Body(e).vector(), before.Body(e).vector()) << ToString(kind) << " body " << e;
    }
    EXPECT_EQ(after.estimator().parameters().tail(4), fresh.x.tail(4)) << ToString(kind);
    EXPECT_EQ(after.estimator().counters().accepted(), 300u);
  }
}

}  // namespace
}  // namespace inertial
