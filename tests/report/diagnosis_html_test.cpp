// The diagnosis page's helpers: base64 against RFC 4648's test vectors (section 10) and bytes of
// every value, HTML escaping of the four characters that matter.
#include "inertial/report/diagnosis_html.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <string>

namespace inertial {
namespace {

TEST(DiagnosisHtml, Base64IsRfc4648) {
  EXPECT_EQ(Base64(""), "");
  EXPECT_EQ(Base64("f"), "Zg==");
  EXPECT_EQ(Base64("fo"), "Zm8=");
  EXPECT_EQ(Base64("foo"), "Zm9v");
  EXPECT_EQ(Base64("foob"), "Zm9vYg==");
  EXPECT_EQ(Base64("fooba"), "Zm9vYmE=");
  EXPECT_EQ(Base64("foobar"), "Zm9vYmFy");
  // High bytes and NUL: 0x00 0xFF 0xFE -> 000000 001111 111111 111110.
  EXPECT_EQ(Base64(std::string("\x00\xff\xfe", 3)), "AP/+");
  EXPECT_EQ(Base64(std::string("\x89PNG", 4)), "iVBORw==");
}

TEST(DiagnosisHtml, HtmlEscapedEscapesMarkup) {
  EXPECT_EQ(HtmlEscaped("a < b && c > \"d\""), "a &lt; b &amp;&amp; c &gt; &quot;d&quot;");
  EXPECT_EQ(HtmlEscaped("plain 'text' 1.5 N m"), "plain 'text' 1.5 N m");
  EXPECT_NE(std::find(DiagnosisReportFileNames().begin(), DiagnosisReportFileNames().end(), "index.html"),
            DiagnosisReportFileNames().end());
}

}  // namespace
}  // namespace inertial
