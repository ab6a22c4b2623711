// LCM messages decoded without trusting them (lcm_layout.hpp): fingerprints against lcm-gen's
// getHash() of the project's types; messages encoded by lcm-gen's code decoded to the same numbers
// and strings; every primitive type read from bytes written by hand (big-endian, two's complement,
// IEEE float); and each refusal (fingerprint, truncation, left-over bytes, lengths outside their
// cap, strings without terminator, bad layouts) naming what is wrong.
#include "inertial/transport/lcm_layout.hpp"

#include <gtest/gtest.h>

#include <cstring>
#include <stdexcept>

#include "inertial/body_wrench_t.hpp"
#include "inertial/joint_state_t.hpp"
#include "inertial/residual_t.hpp"
#include "inertial/transport/body_message.hpp"
#include "inertial/transport/joint_message.hpp"
#include "transport/big_endian_writer.hpp"

namespace inertial {
namespace {

using testing::Writer;

LcmField F(const char* name, LcmType type, int length = -1, const char* length_field = "") {
  LcmField f;
  f.name = name;
  f.type = type;
  f.length = length;
  f.length_field = length_field;
  return f;
}

const LcmLayout& ResidualLayout() {
  static const LcmLayout layout{"residual_t",
                                {F("utime", LcmType::kInt64), F("status", LcmType::kString),
                                 F("num_channels", LcmType::kInt32),
                                 F("channel_names", LcmType::kString, -1, "num_channels"),
                                 F("measured", LcmType::kDouble, -1, "num_channels"),
                                 F("predicted", LcmType::kDouble, -1, "num_channels"),
                                 F("residual", LcmType::kDouble, -1, "num_channels")}};
  return layout;
}

// Big-endian integers of `bytes` bytes, and a string as LCM writes it (length with terminator).
void Int(Writer* w, std::int64_t v, int bytes) {
  for (int i = bytes - 1; i >= 0; --i) w->bytes.push_back(static_cast<std::uint8_t>(static_cast<std::uint64_t>(v) >> (8 * i)));
}
void Str(Writer* w, const std::string& s) {
  Int(w, static_cast<std::int64_t>(s.size() + 1), 4);
  for (char c : s) w->bytes.push_back(static_cast<std::uint8_t>(c));
  w->bytes.push_back(0);
}

std::string DecodeError(const LcmLayout& layout, const std::vector<std::uint8_t>& bytes, int cap = 4096) {
  try {
    DecodeLcm(layout, bytes.data(), bytes.size(), cap);
  } catch (const LcmDecodeError& e) {
    return e.what();
  }
  return "(decoded)";
}

TEST(LcmLayout, FingerprintsAreLcmGens) {
  EXPECT_EQ(LcmFingerprint(JointStateLayout()), static_cast<std::uint64_t>(inertial::joint_state_t::getHash()));
  EXPECT_EQ(LcmFingerprint(ResidualLayout()), static_cast<std::uint64_t>(inertial::residual_t::getHash()));
  // Fixed-length arrays and booleans.
  EXPECT_EQ(LcmFingerprint(BodyWrenchLayout()), static_cast<std::uint64_t>(inertial::body_wrench_t::getHash()));
  // The type name is not part of it; a field's name, type and dimension are.
  LcmLayout renamed = ResidualLayout();
  renamed.type_name = "other_t";
  EXPECT_EQ(LcmFingerprint(renamed), LcmFingerprint(ResidualLayout()));
  LcmLayout changed = ResidualLayout();
  changed.fields[6].type = LcmType::kFloat;
  EXPECT_NE(LcmFingerprint(changed), LcmFingerprint(ResidualLayout()));
}

TEST(LcmLayout, DecodesWhatLcmGenEncodes) {
  inertial::residual_t r;
  r.utime = -1234567890123;
  r.status = "accepted";
  r.num_channels = 2;
  r.channel_names = {"hip", "knee"};
  r.measured = {1.5, -2.25};
  r.predicted = {1.0, -2.0};
  r.residual = {0.5, -0.25};
  std::vector<std::uint8_t> bytes(static_cast<size_t>(r.getEncodedSize()));
  r.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
  const LcmRecord rec = DecodeLcm(ResidualLayout(), bytes.data(), bytes.size());
  EXPECT_EQ(rec.Numbers("utime"), (std::vector<double>{-1234567890123.0}));
  EXPECT_EQ(rec.Strings("status"), (std::vector<std::string>{"accepted"}));
  EXPECT_EQ(rec.Numbers("num_channels"), (std::vector<double>{2}));
  EXPECT_EQ(rec.Strings("channel_names"), r.channel_names);
  EXPECT_EQ(rec.Numbers("measured"), r.measured);
  EXPECT_EQ(rec.Numbers("residual"), r.residual);
  EXPECT_THROW(rec.Numbers("status"), LcmDecodeError);
  EXPECT_THROW(rec.Strings("measured"), LcmDecodeError);

  inertial::body_wrench_t w;
  w.utime = 5;
  w.frame = "tool0";
  w.has_twist = true;
  w.has_acceleration = false;
  for (int i = 0; i < 6; ++i) {
    w.twist[i] = i;
    w.acceleration[i] = -i;
    w.wrench[i] = 0.5 * i;
  }
  for (int i = 0; i < 3; ++i) w.gravity[i] = i == 2 ? -9.81 : 0.0;
  bytes.assign(static_cast<size_t>(w.getEncodedSize()), 0);
  w.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
  const LcmRecord b = DecodeLcm(BodyWrenchLayout(), bytes.data(), bytes.size());
  EXPECT_EQ(b.Numbers("has_twist"), (std::vector<double>{1}));
  EXPECT_EQ(b.Numbers("has_acceleration"), (std::vector<double>{0}));
  EXPECT_EQ(b.Numbers("wrench"), (std::vector<double>{0, 0.5, 1, 1.5, 2, 2.5}));
  EXPECT_EQ(b.Numbers("gravity"), (std::vector<double>{0, 0, -9.81}));
  EXPECT_EQ(b.Strings("frame"), (std::vector<std::string>{"tool0"}));
}

TEST(LcmLayout, EveryPrimitiveTypeFromHandWrittenBytes) {
  const LcmLayout layout{"all_t",
                         {F("a", LcmType::kInt8), F("b", LcmType::kInt16), F("c", LcmType::kInt32),
                          F("d", LcmType::kInt64), F("e", LcmType::kByte), F("f", LcmType::kFloat),
                          F("g", LcmType::kDouble), F("h", LcmType::kBoolean), F("i", LcmType::kString),
                          F("n", LcmType::kInt8), F("v", LcmType::kInt16, -1, "n")}};
  Writer w;
  w.U64(LcmFingerprint(layout));
  Int(&w, -3, 1);
  Int(&w, -300, 2);
  Int(&w, -70000, 4);
  Int(&w, -(std::int64_t{1} << 40), 8);
  Int(&w, 200, 1);
  w.F32(1.5f);
  std::uint64_t bits;
  const double g = -0.1;
  std::memcpy(&bits, &g, 8);
  w.U64(bits);
  Int(&w, 2, 1);  // any non-zero byte is true
  Str(&w, "hi");
  Int(&w, 3, 1);
  for (int k : {7, -8, 9}) Int(&w, k, 2);
  const LcmRecord r = DecodeLcm(layout, w.bytes.data(), w.bytes.size());
  EXPECT_EQ(r.Numbers("a")[0], -3);
  EXPECT_EQ(r.Numbers("b")[0], -300);
  EXPECT_EQ(r.Numbers("c")[0], -70000);
  EXPECT_EQ(r.Numbers("d")[0], -1099511627776.0);
  EXPECT_EQ(r.Numbers("e")[0], 200);
  EXPECT_EQ(r.Numbers("f")[0], 1.5);
  EXPECT_EQ(r.Numbers("g")[0], -0.1);
  EXPECT_EQ(r.Numbers("h")[0], 1);
  EXPECT_EQ(r.Strings("i")[0], "hi");
  EXPECT_EQ(r.Numbers("v"), (std::vector<double>{7, -8, 9}));
  for (LcmType t : {LcmType::kInt8, LcmType::kInt16, LcmType::kInt32, LcmType::kInt64, LcmType::kByte,
                    LcmType::kFloat, LcmType::kDouble, LcmType::kString, LcmType::kBoolean}) {
    EXPECT_NE(std::string(ToString(t)), "?");
  }
  EXPECT_STREQ(ToString(LcmType::kInt16), "int16_t");
  EXPECT_STREQ(ToString(LcmType::kBoolean), "boolean");
}

TEST(LcmLayout, RefusesWhatItCannotTrust) {
  const LcmLayout layout{"msg_t", {F("n", LcmType::kInt32), F("x", LcmType::kDouble, -1, "n"), F("s", LcmType::kString)}};
  auto message = [&](std::int64_t n, int doubles, const std::string& s) {
    Writer w;
    w.U64(LcmFingerprint(layout));
    Int(&w, n, 4);
    for (int i = 0; i < doubles; ++i) w.U64(0);
    Str(&w, s);
    return w.bytes;
  };
  std::vector<std::uint8_t> good = message(2, 2, "ok");
  EXPECT_EQ(DecodeLcm(layout, good.data(), good.size()).Numbers("x").size(), 2u);

  std::vector<std::uint8_t> bad = good;
  bad[0] ^= 1;
  EXPECT_EQ(DecodeError(layout, bad).rfind("wrong fingerprint 0x", 0), 0u);
  EXPECT_NE(DecodeError(layout, bad).find("for msg_t"), std::string::npos);
  bad.assign(good.begin(), good.end() - 1);
  // 8 (fingerprint) + 4 (n) + 16 (x) + 4 + 3 ("ok\0") = 35 bytes, one cut off.
  EXPECT_EQ(DecodeError(layout, bad), "truncated: string 's' needs 3 bytes, 2 left of 34");
  bad = good;
  bad.push_back(0);
  EXPECT_EQ(DecodeError(layout, bad), "1 bytes left over after the last field");
  EXPECT_EQ(DecodeError(layout, message(-1, 0, "ok")), "field 'x': length n = -1 is outside [0, 4096]");
  EXPECT_EQ(DecodeError(layout, good, 1), "field 'x': length n = 2 is outside [0, 1]");
  bad = good;
  bad.back() = 'x';  // the terminator overwritten
  EXPECT_EQ(DecodeError(layout, bad), "string 's' is not terminated");
  bad = good;
  bad.resize(bad.size() - 7);  // "ok\0" and its length gone; a length of 0 instead
  Writer zero;
  Int(&zero, 0, 4);
  bad.insert(bad.end(), zero.bytes.begin(), zero.bytes.end());
  EXPECT_EQ(DecodeError(layout, bad), "string 's': length 0 (no terminator)");
  EXPECT_EQ(DecodeError(layout, std::vector<std::uint8_t>(5, 0)).rfind("truncated: the fingerprint needs 8 bytes", 0), 0u);
  EXPECT_THROW(DecodeLcm(layout, nullptr, 0), LcmDecodeError);
  const LcmLayout fixed{"", {F("x", LcmType::kDouble, 5)}};
  Writer five;
  five.U64(LcmFingerprint(fixed));
  for (int i = 0; i < 5; ++i) five.U64(0);
  EXPECT_EQ(DecodeError(fixed, five.bytes, 4), "field 'x': 5 elements, more than 4");
}

TEST(LcmLayout, RejectsBadLayouts) {
  EXPECT_THROW(CheckLcmLayout(LcmLayout{}), std::invalid_argument);
  EXPECT_THROW(CheckLcmLayout(LcmLayout{"", {F("", LcmType::kDouble)}}), std::invalid_argument);
  EXPECT_THROW(CheckLcmLayout(LcmLayout{"", {F("a", LcmType::kDouble), F("a", LcmType::kInt8)}}), std::invalid_argument);
  // The length must be an earlier integer scalar: not later, not a double, not an array.
  EXPECT_THROW(CheckLcmLayout(LcmLayout{"", {F("x", LcmType::kDouble, -1, "n"), F("n", LcmType::kInt32)}}),
               std::invalid_argument);
  EXPECT_THROW(CheckLcmLayout(LcmLayout{"", {F("n", LcmType::kDouble), F("x", LcmType::kDouble, -1, "n")}}),
               std::invalid_argument);
  EXPECT_THROW(CheckLcmLayout(LcmLayout{"", {F("n", LcmType::kInt32, 2), F("x", LcmType::kDouble, -1, "n")}}),
               std::invalid_argument);
  EXPECT_THROW(CheckLcmLayout(LcmLayout{"", {F("n", LcmType::kInt32), F("x", LcmType::kDouble, 3, "n")}}),
               std::invalid_argument);
  EXPECT_THROW(LcmFingerprint(LcmLayout{}), std::invalid_argument);
  try {
    CheckLcmLayout(LcmLayout{"", {F("len", LcmType::kInt16), F("a", LcmType::kInt8), F("a", LcmType::kInt8)}});
    ADD_FAILURE() << "accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "LCM layout: field 'a' given twice");
  }
  EXPECT_NO_THROW(CheckLcmLayout(LcmLayout{"", {F("len", LcmType::kInt16), F("x", LcmType::kString, -1, "len")}}));
}

}  // namespace
}  // namespace inertial
