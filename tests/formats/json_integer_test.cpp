// Integers read from JSON checked as integers in range before any conversion (issue 35): what
// nlohmann's get<int>() made undefined (1e308) or truncated (1.9) is refused; whole floats are
// integers (JSON does not tell 2 from 2.0); the edges of the 64-bit types are exact.
#include "inertial/formats/json_integer.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <limits>

namespace inertial {
namespace {

using nlohmann::json;

TEST(JsonInteger, RefusesWhatIsNotAWholeNumberInRange) {
  for (const char* text : {"1e308", "-1e308", "1.9", "-0.5", "\"3\"", "true", "null", "[1]", "{}", "11", "-11",
                           "18446744073709551615", "9223372036854775808", "9.3e18"}) {
    EXPECT_FALSE(JsonInteger(json::parse(text), -10, 10)) << text;
  }
  EXPECT_FALSE(JsonInteger(json::parse("5"), 6, 10));
}

TEST(JsonInteger, AcceptsIntegersAndWholeFloatsInRange) {
  EXPECT_EQ(JsonInteger(json::parse("7"), -10, 10), 7);
  EXPECT_EQ(JsonInteger(json::parse("-10"), -10, 10), -10);
  EXPECT_EQ(JsonInteger(json::parse("10.0"), -10, 10), 10);
  EXPECT_EQ(JsonInteger(json::parse("-0.0"), -10, 10), 0);
  EXPECT_EQ(JsonInteger(json::parse("2e1"), 0, 100), 20);
  constexpr std::int64_t lo = std::numeric_limits<std::int64_t>::min(), hi = std::numeric_limits<std::int64_t>::max();
  EXPECT_EQ(JsonInteger(json::parse("9223372036854775807"), lo, hi), hi);
  EXPECT_EQ(JsonInteger(json::parse("-9223372036854775808"), lo, hi), lo);
  EXPECT_EQ(JsonInteger(json::parse("-9.223372036854775808e18"), lo, hi), lo);  // -2^63 is exact in a double
  EXPECT_FALSE(JsonInteger(json::parse("9.223372036854775808e18"), lo, hi));     // 2^63 is not an int64
}

TEST(JsonUnsigned, CountersUpToTheLargest) {
  constexpr std::uint64_t max = std::numeric_limits<std::uint64_t>::max();
  EXPECT_EQ(JsonUnsigned(json::parse("18446744073709551615"), max), max);
  EXPECT_EQ(JsonUnsigned(json::parse("0"), max), 0u);
  EXPECT_EQ(JsonUnsigned(json::parse("3.0"), max), 3u);
  for (const char* text : {"-1", "2.5", "1e300", "1.8446744073709552e19", "\"1\"", "false"}) {
    EXPECT_FALSE(JsonUnsigned(json::parse(text), max)) << text;
  }
  EXPECT_FALSE(JsonUnsigned(json::parse("101"), 100));
  EXPECT_EQ(JsonUnsigned(json::parse("-0"), max), 0u);  // nlohmann reads -0 as a signed integer
}

// A bound that is not exact as a double (2^62 - 1 rounds up to 2^62) still bounds whole floats.
TEST(JsonInteger, BoundsAreComparedAsIntegers) {
  constexpr std::int64_t hi = (std::int64_t{1} << 62) - 1;
  EXPECT_FALSE(JsonInteger(json::parse("4.611686018427387904e18"), 0, hi));  // 2^62
  EXPECT_EQ(JsonInteger(json::parse("4611686018427387903"), 0, hi), hi);
  EXPECT_FALSE(JsonUnsigned(json::parse("4.611686018427387904e18"), static_cast<std::uint64_t>(hi)));
}

TEST(JsonInteger, TheRefusalShowsTheValueAsWritten) {
  EXPECT_EQ(NotAnIntegerText(json::parse("1.9"), 1, 100000), "is 1.9, not an integer from 1 to 100000");
  EXPECT_EQ(NotAnIntegerText(json::parse("1e308"), 1, 100000), "is 1e+308, not an integer from 1 to 100000");
  EXPECT_EQ(NotAnIntegerText(json::parse("\"" + std::string(100, 'x') + "\""), 0, 1),
            "is \"" + std::string(40, 'x') + "\"..., not an integer from 0 to 1");
  // Arrays and objects by their kind: writing 200,000 levels of nesting out overflowed the stack.
  const std::string deep = std::string(200000, '[') + std::string(200000, ']');
  EXPECT_EQ(NotAnIntegerText(json::parse(deep), 1, 2), "is an array, not an integer from 1 to 2");
  EXPECT_EQ(NotAnIntegerText(json::parse(R"({"a": 1})"), 1, 2), "is an object, not an integer from 1 to 2");
}

}  // namespace
}  // namespace inertial
