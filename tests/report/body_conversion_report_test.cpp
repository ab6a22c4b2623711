// The text, JSON and notes of a converted body, on conversions written out by hand (no conversion
// is run here): the exact strings `inertial convert` prints.
#include "inertial/report/body_conversion_report.hpp"

#include <gtest/gtest.h>

namespace inertial {
namespace {

BodyConversion Made(const std::string& to, const Eigen::MatrixXd& value, bool consistent, bool check_passes) {
  BodyConversion c;
  c.to = to;
  c.value = value;
  c.consistent = consistent;
  c.consistency.finite = c.consistency.mass_positive = c.consistency.inertia_positive_definite_com =
      c.consistency.triangle_inequalities = c.consistency.pseudo_inertia_positive_definite = check_passes;
  c.consistency.mass = 1.5;
  c.consistency.min_triangle_margin = -0.25;
  if (!check_passes) c.consistency.reason = "too thin";
  return c;
}

TEST(BodyConversionReport, AColumnOnOneLineWithRoundTripDigitsAndNoNegativeZero) {
  Eigen::VectorXd v(4);
  v << 1.0, -0.0, 0.1, -2.5e-7;
  EXPECT_EQ(BodyConversionText(Made("pi", v, true, true)), "pi: 1 0 0.10000000000000001 -2.4999999999999999e-07\n");
}

TEST(BodyConversionReport, AMatrixOneRowPerLineUnderTheFirstNumber) {
  Eigen::MatrixXd m(2, 3);
  m << 1, 2, 3, 4, 5, -0.0;
  EXPECT_EQ(BodyConversionText(Made("pseudo", m, true, true)), "pseudo: 1 2 3\n        4 5 0\n");
}

TEST(BodyConversionReport, JsonKeyIsTheRepresentationAndMatricesAreRows) {
  Eigen::MatrixXd m(2, 2);
  m << 1, 2, 3, 4;
  const nlohmann::json j = BodyConversionJson(Made("spatial", m, true, false));
  EXPECT_EQ(j["spatial"], nlohmann::json::parse("[[1.0, 2.0], [3.0, 4.0]]"));
  EXPECT_EQ(j["consistency"]["fully_consistent"], true);
  EXPECT_EQ(j["consistency"]["margins_above_tolerance"], false);
  EXPECT_EQ(j["consistency"]["mass"], 1.5);
  EXPECT_EQ(j["consistency"]["min_triangle_margin"], -0.25);
  EXPECT_EQ(j["consistency"]["reason"], "too thin");
  Eigen::VectorXd v(2);
  v << 0.5, 7;
  EXPECT_EQ(BodyConversionJson(Made("pi", v, true, true))["pi"], nlohmann::json::parse("[0.5, 7.0]"));
}

TEST(BodyConversionReport, NoteOnlyWhenTheCheckCannotConfirm) {
  const Eigen::VectorXd v = Eigen::VectorXd::Ones(10);
  EXPECT_EQ(BodyConversionNote(Made("pi", v, true, true)), "");
  EXPECT_EQ(BodyConversionNote(Made("pi", v, false, false)), "warning: too thin\n");
  EXPECT_EQ(BodyConversionNote(Made("pi", v, true, false)),
            "note: consistent by construction (finite theta), but so thin that the numerical check cannot confirm "
            "it: too thin\n");
}

}  // namespace
}  // namespace inertial
