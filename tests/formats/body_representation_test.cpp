// ConvertBody against hand-worked bodies: the log-Cholesky closed form at simple theta (eq. 8 with
// J0 = 1), the parallel-axis theorem for a solid box off the origin, the pseudo-inertia and spatial
// inertia of known bodies, and every refusal.
#include "inertial/formats/body_representation.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace inertial {
namespace {

std::vector<double> Column(const Eigen::MatrixXd& m) {
  EXPECT_EQ(m.cols(), 1);
  return std::vector<double>(m.data(), m.data() + m.rows());
}

BodyConversion Convert(const std::string& from, const std::string& to, const std::vector<double>& values,
                       bool allow_inconsistent = false) {
  BodyConversionRequest r;
  r.from = from;
  r.to = to;
  r.values = values;
  r.allow_inconsistent = allow_inconsistent;
  return ConvertBody(r);
}

void ExpectNear(const std::vector<double>& actual, const std::vector<double>& expected, double tol = 1e-12) {
  ASSERT_EQ(actual.size(), expected.size());
  for (std::size_t i = 0; i < actual.size(); ++i) EXPECT_NEAR(actual[i], expected[i], tol) << "entry " << i;
}

// The unit body (1 kg at the origin, second moments 1 kg m^2): J = 1, I = 2 kg m^2 about each axis.
const std::vector<double> kUnitPi = {1, 0, 0, 0, 2, 2, 2, 0, 0, 0};

TEST(BodyRepresentation, SizesOfEveryRepresentation) {
  const std::map<std::string, int> expected = {{"mci", 10}, {"pi", 10}, {"pseudo", 16}, {"spatial", 36}, {"theta", 10}};
  EXPECT_EQ(BodyRepresentationSizes(), expected);
}

TEST(BodyRepresentation, ThetaZeroIsTheUnitBody) {
  ExpectNear(Column(Convert("theta", "pi", std::vector<double>(10, 0.0)).value), kUnitPi);
  ExpectNear(Column(Convert("pi", "theta", kUnitPi).value), std::vector<double>(10, 0.0));
}

TEST(BodyRepresentation, ThetaAlphaScalesTheMassAndTTranslates) {
  // e^{2 alpha} = 3: J = 3 * 1, so m = 3 and I = 6 about each axis.
  std::vector<double> theta(10, 0.0);
  theta[0] = 0.5 * std::log(3.0);
  ExpectNear(Column(Convert("theta", "pi", theta).value), {3, 0, 0, 0, 6, 6, 6, 0, 0, 0});
  // t = (0.1, 0, 0): h = t, Sigma = 1 + t t^T, so Ixx = 2, Iyy = Izz = 2.01.
  std::vector<double> shifted(10, 0.0);
  shifted[7] = 0.1;
  ExpectNear(Column(Convert("theta", "pi", shifted).value), {1, 0.1, 0, 0, 2, 2.01, 2.01, 0, 0, 0});
}

TEST(BodyRepresentation, MciToPiIsTheParallelAxisTheorem) {
  // Solid box 2 kg, 0.3 x 0.4 x 0.5 m, centroid at (0.1, 0, 0.05): I_com = m/12 (b^2 + c^2, ...).
  const double ixx = 2.0 / 12 * (0.16 + 0.25), iyy = 2.0 / 12 * (0.09 + 0.25), izz = 2.0 / 12 * (0.09 + 0.16);
  const std::vector<double> mci = {2, 0.1, 0, 0.05, ixx, iyy, izz, 0, 0, 0};
  // I_origin = I_com + m (|c|^2 1 - c c^T), |c|^2 = 0.0125.
  const std::vector<double> pi = {2, 0.2, 0, 0.1, ixx + 0.005, iyy + 0.025, izz + 0.02, 0, 0, -0.01};
  ExpectNear(Column(Convert("mci", "pi", mci).value), pi);
  ExpectNear(Column(Convert("pi", "mci", pi).value), mci);
}

TEST(BodyRepresentation, PseudoAndSpatialOfKnownBodies) {
  const BodyConversion pseudo = Convert("pi", "pseudo", kUnitPi);
  EXPECT_TRUE(pseudo.value.isApprox(Eigen::MatrixXd::Identity(4, 4), 1e-14)) << pseudo.value;
  // h = (0.1, 0, 0): spatial [[I, S(h)], [S(h)^T, m 1]] with S(h)(1, 2) = -hx, S(h)(2, 1) = hx.
  const Eigen::MatrixXd spatial = Convert("pi", "spatial", {1, 0.1, 0, 0, 2, 2.01, 2.01, 0, 0, 0}).value;
  ASSERT_EQ(spatial.rows(), 6);
  ASSERT_EQ(spatial.cols(), 6);
  EXPECT_DOUBLE_EQ(spatial(0, 0), 2.0);
  EXPECT_DOUBLE_EQ(spatial(1, 1), 2.01);
  EXPECT_DOUBLE_EQ(spatial(1, 5), -0.1);
  EXPECT_DOUBLE_EQ(spatial(2, 4), 0.1);
  EXPECT_DOUBLE_EQ(spatial(5, 1), -0.1);
  EXPECT_DOUBLE_EQ(spatial(3, 3), 1.0);
  // Row by row back to pi.
  std::vector<double> rows;
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j) rows.push_back(spatial(i, j));
  ExpectNear(Column(Convert("spatial", "pi", rows).value), {1, 0.1, 0, 0, 2, 2.01, 2.01, 0, 0, 0});
}

TEST(BodyRepresentation, ThetaRelativeToAReferenceIsZeroAtTheReference) {
  BodyConversionRequest r;
  r.from = "pi";
  r.to = "theta";
  r.values = {2, 0.2, 0, 0.1, 0.05, 0.06, 0.04, 0, 0, -0.005};
  r.reference = InertialParams::FromVector(Eigen::Map<const Vector10>(r.values.data()));
  ExpectNear(Column(ConvertBody(r).value), std::vector<double>(10, 0.0), 1e-10);
  // theta -> theta with a reference: the input unchanged.
  r.from = "theta";
  r.values = {0.1, 0.2, -0.3, 0.1, 0.05, 0.02, 0.01, 0.3, -0.2, 0.1};
  ExpectNear(Column(ConvertBody(r).value), r.values, 0.0);
}

TEST(BodyRepresentation, InconsistentBodiesOnlyWhenAllowedAndNeverToTheta) {
  const std::vector<double> thin = {1, 0, 0, 0, 1, 1, 5, 0, 0, 0};  // Izz > Ixx + Iyy
  EXPECT_THROW(Convert("pi", "pi", thin), std::invalid_argument);
  const BodyConversion allowed = Convert("pi", "pi", thin, true);
  EXPECT_FALSE(allowed.consistent);
  EXPECT_FALSE(allowed.consistency.fully_consistent());
  ExpectNear(Column(allowed.value), thin, 0.0);
  EXPECT_THROW(Convert("pi", "theta", thin, true), std::invalid_argument);
}

TEST(BodyRepresentation, AThinFiniteThetaIsConsistentByConstruction) {
  // e^{-30} stretches: margins below the check's tolerance, still a body.
  const BodyConversion c = Convert("theta", "pi", {-30, -30, -30, -30, 0, 0, 0, 0, 0, 0});
  EXPECT_TRUE(c.consistent);
  EXPECT_FALSE(c.consistency.fully_consistent());
  EXPECT_NEAR(c.value(0, 0), std::exp(-60.0), 1e-40);
}

TEST(BodyRepresentation, NumbersThatAreNoBodyAreRefused) {
  EXPECT_THROW(Convert("mci", "pi", {0, 0.1, 0, 0, 1, 1, 1, 0, 0, 0}), std::invalid_argument);
  EXPECT_THROW(Convert("pi", "mci", {0, 0, 0, 0, 1, 1, 1, 0, 0, 0}, true), std::invalid_argument);
  EXPECT_THROW(Convert("theta", "pi", {400, 0, 0, 0, 0, 0, 0, 0, 0, 0}), std::invalid_argument);
  std::vector<double> asymmetric(16, 0.0);
  asymmetric[0] = asymmetric[5] = asymmetric[10] = asymmetric[15] = 1.0;
  asymmetric[1] = 2.0;
  EXPECT_THROW(Convert("pseudo", "pi", asymmetric, true), std::invalid_argument);
  EXPECT_THROW(Convert("pi", "pi", {1, 0, 0}), std::invalid_argument);
  EXPECT_THROW(Convert("kg", "pi", kUnitPi), std::out_of_range);
  EXPECT_THROW(Convert("pi", "kg", kUnitPi), std::out_of_range);
}

}  // namespace
}  // namespace inertial
