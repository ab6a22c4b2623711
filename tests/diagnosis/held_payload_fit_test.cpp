// The payload a bent link would have to carry (held_payload_fit.hpp): the point mass's pi and its
// Jacobian against finite differences; a link of a CAD error carrying a point payload gives back
// that payload's mass and COM; a departure that would need a payload beyond the region is fitted
// inside it and leaves the link far from its URDF; inputs that allow no fit give none.
#include "inertial/diagnosis/held_payload_fit.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "inertial/estimation/batch/region_barrier.hpp"
#include "inertial/inertia/closed_form_bodies.hpp"
#include "inertial/inertia/plausibility.hpp"
#include "test_support.hpp"

namespace inertial {
namespace {

TEST(HeldPayloadFit, PointMassPiAndItsJacobian) {
  testing::Rng rng(41);
  for (int trial = 0; trial < 20; ++trial) {
    const double m = 0.1 + rng.Uniform(0.0, 3.0);
    const Vector3 c = rng.UniformVector<3>(-0.5, 0.5);
    Eigen::Matrix<double, 10, 3> J;
    const Vector10 pi = PointMassPi(m, c, &J);
    // Independent: a solid sphere of vanishing radius at c (closed_form_bodies.hpp).
    Pose at;
    at.p_BoCo_B = c;
    EXPECT_LT((pi - SolidSphere(m, 1e-9, at).vector()).norm(), 1e-12 * (1.0 + pi.norm()));
    for (int k = 0; k < 3; ++k) {
      const double h = 1e-6;
      Vector3 cp = c, cm = c;
      cp[k] += h;
      cm[k] -= h;
      const Vector10 fd = (PointMassPi(m, cp, nullptr) - PointMassPi(m, cm, nullptr)) / (2 * h);
      EXPECT_LT((fd - J.col(k)).norm(), 1e-7 * (1.0 + fd.norm())) << k;
    }
  }
}

// A link (a rod 0.34 m long hanging along -z, as the leg's shank) estimated with a CAD error of
// 5 % and a 0.5 kg point payload at its tip, under a covariance of 1 % of each component.
struct Case {
  InertialParams prior, estimate;
  Matrix10 covariance;
};

Case LinkWithPayload(double payload_mass, const Vector3& payload_com) {
  Pose along;
  along.p_BoCo_B = Vector3(0, 0, -0.17);
  Case k;
  k.prior = SolidCylinder(0.45, 0.015, 0.30, along);
  const InertialParams cad = SolidCylinder(0.45 * 1.05, 0.015, 0.30 * 1.03, along);
  k.estimate = InertialParams::FromVector(cad.vector() + PointMassPi(payload_mass, payload_com));
  const Vector10 s = (0.01 * k.estimate.vector().cwiseAbs()).cwiseMax(1e-8);
  k.covariance = s.cwiseProduct(s).asDiagonal();
  return k;
}

TEST(HeldPayloadFit, APayloadAtTheLinksTipIsFoundAndTakesItBack) {
  const Case k = LinkWithPayload(0.5, Vector3(0, 0, -0.34));
  const std::optional<HeldPayloadFit> fit = FitHeldPayload(k.estimate, k.prior, k.covariance, 0.34);
  ASSERT_TRUE(fit);
  EXPECT_TRUE(fit->converged);
  EXPECT_NEAR(fit->payload.mass(), 0.5, 0.05);
  EXPECT_LT((fit->payload.com() - Vector3(0, 0, -0.34)).norm(), 0.03);
  EXPECT_GE(fit->slack, kBarrierOnset);  // not pinned: the barrier plays no part
  EXPECT_LT(fit->chi2, 0.05 * fit->chi2_held);
  EXPECT_EQ(fit->rank, 10);
  // What is left is the link's CAD error: within the tolerance of its URDF.
  const BodyPlausibility left =
      MeasurePlausibility(InertialParams::FromVector(k.estimate.vector() - fit->payload.vector()), k.prior);
  EXPECT_TRUE(left.Within(kDefaultPriorTolerance)) << left.factor;
}

TEST(HeldPayloadFit, APayloadBeyondTheRegionIsFittedInsideItAndLeavesTheLinkBent) {
  const Case k = LinkWithPayload(0.3, Vector3(0.6, 0.3, 0.2));  // 0.7 m from a link that reaches 0.34 m
  const std::optional<HeldPayloadFit> fit = FitHeldPayload(k.estimate, k.prior, k.covariance, 0.34);
  ASSERT_TRUE(fit);
  EXPECT_GT(fit->slack, 0.0);
  EXPECT_LT(fit->slack, kBarrierOnset);  // pinned where the barrier begins: the data want it farther
  EXPECT_LT(fit->payload.com().norm(), 0.34 / 0.9 + 1e-9);  // ShapePointsOfSphere's circumscribed ball
  EXPECT_NEAR(fit->region_radius, 0.34 / 0.9, 0.01);
  const Vector10 rest = k.estimate.vector() - fit->payload.vector();
  bool bent = true;
  try {
    bent = !MeasurePlausibility(InertialParams::FromVector(rest), k.prior).Within(kDefaultPriorTolerance);
  } catch (const std::invalid_argument&) {  // no body: bent all the same
  }
  EXPECT_TRUE(bent);
}

TEST(HeldPayloadFit, NoFitWithoutAnAddedMassOrACovariance) {
  const Case k = LinkWithPayload(0.5, Vector3(0, 0, -0.34));
  EXPECT_FALSE(FitHeldPayload(k.prior, k.estimate, k.covariance, 0.34));  // lighter than its URDF
  EXPECT_FALSE(FitHeldPayload(k.estimate, k.prior, Matrix10::Zero(), 0.34));
  EXPECT_FALSE(FitHeldPayload(k.estimate, k.prior, k.covariance, 0.0));
  Matrix10 nan = k.covariance;
  nan(3, 3) = std::nan("");
  EXPECT_FALSE(FitHeldPayload(k.estimate, k.prior, nan, 0.34));
  EXPECT_FALSE(FitHeldPayload(k.estimate, k.prior, k.covariance, 1e-9));  // no region to draw
}

// Starts far outside the region, or an added mass beyond what the region can hold: the fit stays
// inside the region and below its mass bound, or gives nothing.
TEST(HeldPayloadFit, DegenerateDeparturesStayInsideTheRegionOrGiveNothing) {
  const Case k = LinkWithPayload(0.5, Vector3(0, 0, -0.34));
  for (const Vector10& added : {(Vector10() << 1e-5, 0.05, 0, 0, 0, 0, 0, 0, 0, 0).finished(),
                                (Vector10() << 5e4, 0, 0, -1e4, 0, 0, 0, 0, 0, 0).finished()}) {
    const InertialParams estimate = InertialParams::FromVector(k.prior.vector() + added);
    const std::optional<HeldPayloadFit> fit = FitHeldPayload(estimate, k.prior, k.covariance, 0.34);
    if (!fit) continue;
    EXPECT_GT(fit->slack, 0.0);
    EXPECT_LT(fit->payload.com().norm(), 0.34 / 0.9 + 1e-9);
    EXPECT_LT(fit->payload.mass(), 7850.0 * 4.0 / 3.0 * std::acos(-1.0) * std::pow(fit->region_radius, 3) * 1.01);
  }
}

// The fit's chi2 is taken in the body's units: with a covariance of 1 % of each component and a
// floor of 1e-8 (a product of inertia that is zero known to 1e-8 kg m^2), every direction is
// judged, and a payload of 2 kg at 0.3 m on the rod is found.
TEST(HeldPayloadFit, EveryDirectionIsJudgedWhateverItsUnit) {
  Case k = LinkWithPayload(2.0, Vector3(0, 0, -0.3));
  const Vector10 s = (0.01 * k.estimate.vector().cwiseAbs()).cwiseMax(1e-8);
  k.covariance = s.cwiseProduct(s).asDiagonal();
  const std::optional<HeldPayloadFit> fit = FitHeldPayload(k.estimate, k.prior, k.covariance, 0.34);
  ASSERT_TRUE(fit);
  EXPECT_EQ(fit->rank, 10);
  EXPECT_NEAR(fit->payload.mass(), 2.0, 0.1);
  EXPECT_LT((fit->payload.com() - Vector3(0, 0, -0.3)).norm(), 0.02);
}

}  // namespace
}  // namespace inertial
