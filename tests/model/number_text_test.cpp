// Numbers as text (number_text.hpp): hand-written expected strings (what C's printf rules give for
// %.ng and %.nf), and the exact form against strtod: it reads back bit for bit, over seeded random
// doubles of every magnitude (subnormals included) and the special values, and one digit fewer
// would not.
#include "inertial/model/number_text.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>

namespace inertial {
namespace {

std::uint64_t Bits(double x) {
  std::uint64_t b;
  std::memcpy(&b, &x, sizeof b);
  return b;
}

double FromBits(std::uint64_t b) {
  double x;
  std::memcpy(&x, &b, sizeof x);
  return x;
}

TEST(FormatNumber, WritesSignificantDigitsAsPrintfG) {
  EXPECT_EQ(FormatNumber(0.123456), "0.1235");
  EXPECT_EQ(FormatNumber(1234567.0), "1.235e+06");
  EXPECT_EQ(FormatNumber(2.5), "2.5");
  EXPECT_EQ(FormatNumber(100.0), "100");
  EXPECT_EQ(FormatNumber(-0.00012345), "-0.0001234");  // the double is just below 1.2345e-4
  EXPECT_EQ(FormatNumber(0.000012345, 3), "1.23e-05");
  EXPECT_EQ(FormatNumber(0.5, 1), "0.5");
  EXPECT_EQ(FormatNumber(9.99, 2), "10");
  EXPECT_EQ(FormatNumber(1.0 / 3.0, 6), "0.333333");
  EXPECT_EQ(FormatNumber(0.001, 6), "0.001");
  EXPECT_EQ(FormatNumber(1e-9, 6), "1e-09");
  EXPECT_EQ(FormatNumber(0.1, 17), "0.10000000000000001");
  EXPECT_EQ(FormatNumber(-2.5e-7, 17), "-2.4999999999999999e-07");
  EXPECT_EQ(FormatNumber(1e300, 17), "1.0000000000000001e+300");
  EXPECT_EQ(FormatNumber(-std::numeric_limits<double>::max(), 17), "-1.7976931348623157e+308");
  EXPECT_EQ(FormatNumber(0.0), "0");
  EXPECT_EQ(FormatNumber(-0.0), "-0");
  EXPECT_EQ(FormatNumber(std::numeric_limits<double>::infinity()), "inf");
  EXPECT_EQ(FormatNumber(-std::numeric_limits<double>::infinity(), 3), "-inf");
  EXPECT_EQ(FormatNumber(std::numeric_limits<double>::quiet_NaN()), "nan");
}

TEST(FormatNumber, RefusesDigitsOutsideOneToSeventeen) {
  EXPECT_THROW(FormatNumber(1.0, 0), std::invalid_argument);
  EXPECT_THROW(FormatNumber(1.0, 18), std::invalid_argument);
  EXPECT_NO_THROW(FormatNumber(1.0, 1));
  EXPECT_NO_THROW(FormatNumber(1.0, 17));
}

TEST(FormatNumberExact, WritesTheShortestTextForHandPickedValues) {
  EXPECT_EQ(FormatNumberExact(0.1), "0.1");
  EXPECT_EQ(FormatNumberExact(984844912472848384.0), "984844912472848384");  // shorter than 9.848449124728484e+17
  EXPECT_EQ(FormatNumberExact(-1000.5), "-1000.5");
  EXPECT_EQ(FormatNumberExact(1e300), "1e+300");
  EXPECT_EQ(FormatNumberExact(1.0 / 3.0), "0.3333333333333333");
  EXPECT_EQ(FormatNumberExact(0.1 + 0.2), "0.30000000000000004");
  EXPECT_EQ(FormatNumberExact(std::numeric_limits<double>::denorm_min()), "5e-324");
  EXPECT_EQ(FormatNumberExact(std::numeric_limits<double>::max()), "1.7976931348623157e+308");
  EXPECT_EQ(FormatNumberExact(0.0), "0");
  EXPECT_EQ(FormatNumberExact(-0.0), "-0");
  EXPECT_EQ(FormatNumberExact(std::numeric_limits<double>::infinity()), "inf");
  EXPECT_EQ(FormatNumberExact(-std::numeric_limits<double>::infinity()), "-inf");
  EXPECT_EQ(FormatNumberExact(std::numeric_limits<double>::quiet_NaN()), "nan");
}

// Random bit patterns cover every exponent (subnormals are the patterns with exponent 0), and
// uniform values the everyday range. Each text reads back (strtod) to the same bits and is no
// longer than the shortest printf %.kg (k = 1..17) that reads back: the reference is printf and
// strtod, not std::to_chars.
TEST(FormatNumberExact, ReadsBackBitForBitWithTheFewestDigits) {
  std::mt19937_64 random(20240537);
  std::uniform_real_distribution<double> everyday(-10.0, 10.0);
  std::vector<double> values = {0.0, -0.0, std::numeric_limits<double>::denorm_min(),
                                -std::numeric_limits<double>::denorm_min(), std::numeric_limits<double>::min(),
                                std::nextafter(std::numeric_limits<double>::min(), 0.0),
                                std::numeric_limits<double>::max(), std::numeric_limits<double>::epsilon()};
  for (int k = 0; k < 4000; ++k) {
    const double pattern = FromBits(random());
    if (std::isfinite(pattern)) values.push_back(pattern);
    values.push_back(everyday(random));
    values.push_back(FromBits(random() & 0x800FFFFFFFFFFFFFull));  // subnormal (exponent bits 0)
  }
  int subnormals = 0;
  for (double x : values) {
    if (std::fpclassify(x) == FP_SUBNORMAL) ++subnormals;
    const std::string text = FormatNumberExact(x);
    char* end = nullptr;
    const double back = std::strtod(text.c_str(), &end);
    ASSERT_EQ(*end, '\0') << text;
    ASSERT_EQ(Bits(back), Bits(x)) << text;
    std::size_t shortest_printf = 0;
    for (int k = 1; k <= 17 && shortest_printf == 0; ++k) {
      const std::string g = FormatNumber(x, k);
      if (Bits(std::strtod(g.c_str(), nullptr)) == Bits(x)) shortest_printf = g.size();
    }
    ASSERT_GT(shortest_printf, 0u) << "%.17g always reads back: " << text;
    EXPECT_LE(text.size(), shortest_printf) << text;
  }
  EXPECT_GT(subnormals, 3000);
}

TEST(FormatNumberExact, SpecialValuesReadBack) {
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_EQ(std::strtod(FormatNumberExact(inf).c_str(), nullptr), inf);
  EXPECT_EQ(std::strtod(FormatNumberExact(-inf).c_str(), nullptr), -inf);
  EXPECT_TRUE(std::isnan(std::strtod(FormatNumberExact(std::nan("")).c_str(), nullptr)));
  EXPECT_TRUE(std::signbit(std::strtod(FormatNumberExact(-0.0).c_str(), nullptr)));
}

TEST(FormatFixed, WritesDecimalsAsPrintfF) {
  EXPECT_EQ(FormatFixed(12.345678, 2), "12.35");
  EXPECT_EQ(FormatFixed(0.5, 0), "0");  // round half to even
  EXPECT_EQ(FormatFixed(-1.25, 1), "-1.2");
  EXPECT_EQ(FormatFixed(0.001, 6), "0.001000");
  EXPECT_EQ(FormatFixed(1e20, 1), "100000000000000000000.0");
  EXPECT_EQ(FormatFixed(std::numeric_limits<double>::max(), 0).size(), 309u);
  EXPECT_EQ(FormatFixed(std::numeric_limits<double>::infinity(), 2), "inf");
  EXPECT_THROW(FormatFixed(1.0, -1), std::invalid_argument);
  EXPECT_THROW(FormatFixed(1.0, 18), std::invalid_argument);
}

}  // namespace
}  // namespace inertial
