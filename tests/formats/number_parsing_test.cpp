#include "inertial/formats/number_parsing.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace inertial {
namespace {

// The message of the InvalidNumber thrown by f (fails the test if nothing or something else is thrown).
std::string ErrorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const InvalidNumber& e) {
    return e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "expected InvalidNumber, got another exception: " << e.what();
    return {};
  }
  ADD_FAILURE() << "expected InvalidNumber, nothing was thrown";
  return {};
}

bool Contains(const std::string& haystack, const std::string& needle) {
  return haystack.find(needle) != std::string::npos;
}

// ---------------------------------------------------------------------------------------------
// ParseDouble: valid forms, to the exact double.

TEST(ParseDouble, ValidFormsGiveTheExactDouble) {
  EXPECT_EQ(ParseDouble("1", "x"), 1.0);
  EXPECT_EQ(ParseDouble("-2.5e-3", "x"), -2.5e-3);
  EXPECT_EQ(ParseDouble("+3", "x"), 3.0);
  EXPECT_EQ(ParseDouble(".5", "x"), 0.5);
  EXPECT_EQ(ParseDouble("0.1", "x"), 0.1);  // correctly rounded, not 0.1 + 1 ulp
  EXPECT_EQ(ParseDouble("-0.1", "x"), -0.1);
  EXPECT_EQ(ParseDouble("1E3", "x"), 1000.0);
  EXPECT_EQ(ParseDouble("5.", "x"), 5.0);
  EXPECT_EQ(ParseDouble("+1.5e+2", "x"), 150.0);
  EXPECT_EQ(ParseDouble("007", "x"), 7.0);  // decimal, not octal
  EXPECT_EQ(ParseDouble("1.7976931348623157e308", "x"), std::numeric_limits<double>::max());
  EXPECT_EQ(ParseDouble("-1.7976931348623157e308", "x"), -std::numeric_limits<double>::max());
  EXPECT_EQ(ParseDouble("2.2250738585072014e-308", "x"), std::numeric_limits<double>::min());
  EXPECT_EQ(ParseDouble("4.9406564584124654e-324", "x"), std::numeric_limits<double>::denorm_min());
  // Halfway case between 1 and 1 + 2^-52: rounds to even (1.0).
  EXPECT_EQ(ParseDouble("1.00000000000000011102230246251565404236316680908203125", "x"), 1.0);
}

TEST(ParseDouble, NegativeZeroKeepsItsSign) {
  const double z = ParseDouble("-0", "x");
  EXPECT_EQ(z, 0.0);
  EXPECT_TRUE(std::signbit(z));
  EXPECT_FALSE(std::signbit(ParseDouble("0", "x")));
  EXPECT_FALSE(std::signbit(ParseDouble("+0.0", "x")));
}

// Every double printed with 17 significant digits reads back to itself, and agrees with strtod.
TEST(ParseDouble, SeventeenDigitRoundTripOfRandomDoubles) {
  std::mt19937_64 gen(20220517);
  std::uniform_int_distribution<int> exponent(-300, 300);
  std::uniform_real_distribution<double> mantissa(-10.0, 10.0);
  for (int n = 0; n < 5000; ++n) {
    // The exponent first, as x86-64 drew ldexp's arguments (right to left; aarch64: left to right).
    const int e = exponent(gen);
    const double x = std::ldexp(mantissa(gen), e);
    char buffer[64];
    std::snprintf(buffer, sizeof buffer, "%.17g", x);
    const double parsed = ParseDouble(buffer, "x");
    ASSERT_EQ(parsed, x) << buffer;
    ASSERT_EQ(parsed, std::strtod(buffer, nullptr)) << buffer;
  }
}

// ---------------------------------------------------------------------------------------------
// ParseDouble: garbage is rejected, and the message names the input and the text.

TEST(ParseDouble, GarbageIsRejectedWithInputAndTextInTheMessage) {
  for (const char* text : {"1x", "abc", "1,2", "0x10", "0x1p3", "1 ", " 1", "1e", "e5", "-", "+", "--1", "1..2",
                           "1e5.5", "1 2", "\t3", "4\n", "1_000", "one"}) {
    const std::string message = ErrorOf([&] { ParseDouble(text, "mass of link 3"); });
    EXPECT_TRUE(Contains(message, "mass of link 3")) << "text '" << text << "': " << message;
    EXPECT_TRUE(Contains(message, std::string("'") + text + "'")) << "text '" << text << "': " << message;
    EXPECT_TRUE(Contains(message, "not a number")) << "text '" << text << "': " << message;
  }
}

TEST(ParseDouble, SignAfterAPlusIsRejected) {
  // "+" is accepted as a sign, but only one sign: "+-3" is not a number (and must not read as -3).
  for (const char* text : {"+-3", "++3", "-+3", "+-inf", "+ 3"}) {
    SCOPED_TRACE(text);
    const std::string message = ErrorOf([&] { ParseDouble(text, "arg", true); });
    EXPECT_TRUE(Contains(message, std::string("'") + text + "'")) << message;
  }
}

TEST(ParseDouble, EmptyTextIsRejectedAndNamesTheInput) {
  const std::string message = ErrorOf([] { ParseDouble("", "--reference"); });
  EXPECT_TRUE(Contains(message, "--reference")) << message;
  EXPECT_TRUE(Contains(message, "empty")) << message;
  // Also with allow_non_finite.
  ErrorOf([] { ParseDouble("", "x", true); });
}

TEST(ParseDouble, ErrorIsAnInvalidArgument) {
  // Callers that catch std::invalid_argument see it too.
  EXPECT_THROW(ParseDouble("abc", "x"), std::invalid_argument);
}

// ---------------------------------------------------------------------------------------------
// Non-finite values: rejected unless allowed.

TEST(ParseDouble, NonFiniteRejectedByDefault) {
  for (const char* text : {"nan", "inf", "-inf", "+inf", "NaN", "INF", "infinity", "-Infinity"}) {
    const std::string message = ErrorOf([&] { ParseDouble(text, "argument 2 (pi)"); });
    EXPECT_TRUE(Contains(message, "argument 2 (pi)")) << text << ": " << message;
    EXPECT_TRUE(Contains(message, std::string("'") + text + "'")) << text << ": " << message;
    EXPECT_TRUE(Contains(message, "not finite")) << text << ": " << message;
  }
}

TEST(ParseDouble, NonFiniteAcceptedWhenAllowed) {
  EXPECT_TRUE(std::isnan(ParseDouble("nan", "x", true)));
  EXPECT_EQ(ParseDouble("inf", "x", true), std::numeric_limits<double>::infinity());
  EXPECT_EQ(ParseDouble("-inf", "x", true), -std::numeric_limits<double>::infinity());
  EXPECT_EQ(ParseDouble("+inf", "x", true), std::numeric_limits<double>::infinity());
  EXPECT_EQ(ParseDouble("Infinity", "x", true), std::numeric_limits<double>::infinity());
  // Allowing non-finite values does not make garbage acceptable.
  ErrorOf([] { ParseDouble("infx", "x", true); });
  ErrorOf([] { ParseDouble("abc", "x", true); });
}

// ---------------------------------------------------------------------------------------------
// Out of range.

TEST(ParseDouble, OverflowIsOutOfRange) {
  for (const char* text : {"1e999", "-1e999", "1.8e308", "+1e400"}) {
    const std::string message = ErrorOf([&] { ParseDouble(text, "stdin, value 7"); });
    EXPECT_TRUE(Contains(message, "stdin, value 7")) << text << ": " << message;
    EXPECT_TRUE(Contains(message, std::string("'") + text + "'")) << text << ": " << message;
    EXPECT_TRUE(Contains(message, "range")) << text << ": " << message;
  }
  // Overflow is not silently turned into an infinity even when infinities are allowed.
  ErrorOf([] { ParseDouble("1e999", "x", true); });
}

// ---------------------------------------------------------------------------------------------
// ParseNumberList.

TEST(ParseNumberList, SplitsOnSpacesCommasTabsAndNewlines) {
  const std::vector<double> v = ParseNumberList("1, -2.5e-3\n+3\t.5,0.1\r\n  7  ", "stdin");
  const std::vector<double> expected = {1.0, -2.5e-3, 3.0, 0.5, 0.1, 7.0};
  EXPECT_EQ(v, expected);
}

TEST(ParseNumberList, CommaWithoutSpacesSeparates) {
  const std::vector<double> expected = {1.0, 2.0, 3.0};
  EXPECT_EQ(ParseNumberList("1,2,3", "x"), expected);
  EXPECT_EQ(ParseNumberList("1 ,2 , 3", "x"), expected);
  EXPECT_EQ(ParseNumberList("\n1\n2\n3\n", "x"), expected);
}

TEST(ParseNumberList, EmptyAndBlankTextGiveNoNumbers) {
  EXPECT_TRUE(ParseNumberList("", "x").empty());
  EXPECT_TRUE(ParseNumberList("  \n\t ", "x").empty());
}

// A missing value between commas is an error, not silently skipped; one trailing comma is fine.
TEST(ParseNumberList, MissingValuesBetweenCommasAreErrors) {
  EXPECT_THROW(ParseNumberList(",", "x"), InvalidNumber);
  EXPECT_THROW(ParseNumberList(",1", "x"), InvalidNumber);
  try {
    ParseNumberList("1,,2", "row");
    FAIL();
  } catch (const InvalidNumber& e) {
    EXPECT_NE(std::string(e.what()).find("row, value 2: empty value between commas"), std::string::npos) << e.what();
  }
  EXPECT_THROW(ParseNumberList("1, ,2", "x"), InvalidNumber);
  EXPECT_EQ(ParseNumberList("1,2,", "x"), (std::vector<double>{1.0, 2.0}));
  EXPECT_EQ(ParseNumberList("1 , 2\n3,\n4", "x"), (std::vector<double>{1.0, 2.0, 3.0, 4.0}));
}

TEST(ParseNumberList, ExactValuesOfManyNumbers) {
  std::mt19937_64 gen(7);
  std::uniform_real_distribution<double> u(-1e3, 1e3);
  std::vector<double> expected;
  std::string text;
  for (int i = 0; i < 200; ++i) {
    const double x = u(gen);
    expected.push_back(x);
    char buffer[64];
    std::snprintf(buffer, sizeof buffer, "%.17g", x);
    text += buffer;
    text += (i % 3 == 0) ? ", " : (i % 3 == 1) ? "\n" : " ";
  }
  EXPECT_EQ(ParseNumberList(text, "x"), expected);
}

TEST(ParseNumberList, ErrorNamesTheInputAndThePositionOfTheBadToken) {
  std::string message = ErrorOf([] { ParseNumberList("1, 2, abc, 4", "stdin"); });
  EXPECT_TRUE(Contains(message, "stdin, value 3")) << message;
  EXPECT_TRUE(Contains(message, "'abc'")) << message;
  EXPECT_TRUE(Contains(message, "not a number")) << message;

  message = ErrorOf([] { ParseNumberList("1\n2\n3\n4\n5\nnan", "--reference"); });
  EXPECT_TRUE(Contains(message, "--reference, value 6")) << message;
  EXPECT_TRUE(Contains(message, "'nan'")) << message;
  EXPECT_TRUE(Contains(message, "not finite")) << message;

  message = ErrorOf([] { ParseNumberList("1e999", "file.txt"); });
  EXPECT_TRUE(Contains(message, "file.txt, value 1")) << message;
  EXPECT_TRUE(Contains(message, "'1e999'")) << message;

  // The token is cut at the separator: the message quotes only the bad token.
  message = ErrorOf([] { ParseNumberList("0.5,1x,2", "in"); });
  EXPECT_TRUE(Contains(message, "in, value 2")) << message;
  EXPECT_TRUE(Contains(message, "'1x'")) << message;
  EXPECT_FALSE(Contains(message, "'1x,2'")) << message;
}

TEST(ParseNumberList, NonFiniteValuesAreRejected) {
  EXPECT_THROW(ParseNumberList("1 inf", "x"), InvalidNumber);
  EXPECT_THROW(ParseNumberList("-inf", "x"), InvalidNumber);
  EXPECT_THROW(ParseNumberList("0x10", "x"), InvalidNumber);
  EXPECT_THROW(ParseNumberList("1;2", "x"), InvalidNumber);  // ';' is not a separator
}

}  // namespace
}  // namespace inertial
