#include "inertial/transport/lcm_layout.hpp"

#include <cmath>
#include <cstring>
#include <set>

namespace inertial {
namespace {

// LCM's type-specification hash (the LCM type specification; lcm-gen computes it in signed 64-bit
// arithmetic, so the right shift is arithmetic).
std::int64_t HashUpdate(std::int64_t v, char c) {
  return static_cast<std::int64_t>((static_cast<std::uint64_t>(v) << 8) ^ static_cast<std::uint64_t>(v >> 55)) + c;
}

std::int64_t HashString(std::int64_t v, const std::string& s) {
  v = HashUpdate(v, static_cast<char>(s.size()));
  for (char c : s) v = HashUpdate(v, c);
  return v;
}

int ElementSize(LcmType t) {
  switch (t) {
    case LcmType::kInt8:
    case LcmType::kByte:
    case LcmType::kBoolean: return 1;
    case LcmType::kInt16: return 2;
    case LcmType::kInt32:
    case LcmType::kFloat: return 4;
    case LcmType::kInt64:
    case LcmType::kDouble: return 8;
    case LcmType::kString: return 0;
  }
  return 0;
}

bool IsInteger(LcmType t) {
  return t == LcmType::kInt8 || t == LcmType::kInt16 || t == LcmType::kInt32 || t == LcmType::kInt64;
}

std::uint64_t ReadBigEndian(const unsigned char* p, int bytes) {
  std::uint64_t v = 0;
  for (int i = 0; i < bytes; ++i) v = (v << 8) | p[i];
  return v;
}

double ReadNumber(const unsigned char* p, LcmType t) {
  switch (t) {
    case LcmType::kInt8: return static_cast<std::int8_t>(p[0]);
    case LcmType::kByte: return p[0];
    case LcmType::kBoolean: return p[0] != 0 ? 1.0 : 0.0;
    case LcmType::kInt16: return static_cast<std::int16_t>(ReadBigEndian(p, 2));
    case LcmType::kInt32: return static_cast<std::int32_t>(ReadBigEndian(p, 4));
    case LcmType::kInt64: return static_cast<double>(static_cast<std::int64_t>(ReadBigEndian(p, 8)));
    case LcmType::kFloat: {
      const std::uint32_t bits = static_cast<std::uint32_t>(ReadBigEndian(p, 4));
      float f;
      std::memcpy(&f, &bits, 4);
      return f;
    }
    case LcmType::kDouble: {
      const std::uint64_t bits = ReadBigEndian(p, 8);
      double d;
      std::memcpy(&d, &bits, 8);
      return d;
    }
    case LcmType::kString: break;
  }
  return 0.0;
}

}  // namespace

const char* ToString(LcmType type) {
  switch (type) {
    case LcmType::kInt8: return "int8_t";
    case LcmType::kInt16: return "int16_t";
    case LcmType::kInt32: return "int32_t";
    case LcmType::kInt64: return "int64_t";
    case LcmType::kByte: return "byte";
    case LcmType::kFloat: return "float";
    case LcmType::kDouble: return "double";
    case LcmType::kString: return "string";
    case LcmType::kBoolean: return "boolean";
  }
  return "?";
}

const std::vector<double>& LcmRecord::Numbers(const std::string& field) const {
  const auto it = numbers.find(field);
  if (it == numbers.end()) throw LcmDecodeError("no numeric field '" + field + "'");
  return it->second;
}

const std::vector<std::string>& LcmRecord::Strings(const std::string& field) const {
  const auto it = strings.find(field);
  if (it == strings.end()) throw LcmDecodeError("no string field '" + field + "'");
  return it->second;
}

void CheckLcmLayout(const LcmLayout& layout) {
  std::set<std::string> seen;
  std::map<std::string, const LcmField*> scalars_int;
  if (layout.fields.empty()) throw std::invalid_argument("LCM layout: no fields");
  for (const LcmField& f : layout.fields) {
    if (f.name.empty()) throw std::invalid_argument("LCM layout: a field without a name");
    if (!seen.insert(f.name).second) throw std::invalid_argument("LCM layout: field '" + f.name + "' given twice");
    if (f.length >= 0 && !f.length_field.empty()) {
      throw std::invalid_argument("LCM layout: field '" + f.name + "' has both a fixed length and a length field");
    }
    if (!f.length_field.empty() && scalars_int.count(f.length_field) == 0) {
      throw std::invalid_argument("LCM layout: the length of '" + f.name + "' is '" + f.length_field +
                                  "', which is not an earlier integer scalar field");
    }
    if (!f.is_array() && IsInteger(f.type)) scalars_int[f.name] = &f;
  }
}

std::uint64_t LcmFingerprint(const LcmLayout& layout) {
  CheckLcmLayout(layout);
  std::int64_t v = 0x12345678;
  for (const LcmField& f : layout.fields) {
    v = HashString(v, f.name);
    v = HashString(v, ToString(f.type));
    v = HashUpdate(v, static_cast<char>(f.is_array() ? 1 : 0));
    if (f.is_array()) {
      const bool variable = !f.length_field.empty();
      v = HashUpdate(v, static_cast<char>(variable ? 1 : 0));  // LCM_CONST = 0, LCM_VAR = 1
      v = HashString(v, variable ? f.length_field : std::to_string(f.length));
    }
  }
  const std::uint64_t u = static_cast<std::uint64_t>(v);
  return (u << 1) + ((u >> 63) & 1);
}

LcmRecord DecodeLcm(const LcmLayout& layout, const void* data, std::size_t size, int max_array_length) {
  LcmRecord record;
  DecodeLcmInto(layout, LcmFingerprint(layout), data, size, &record, max_array_length);
  return record;
}

void DecodeLcmInto(const LcmLayout& layout, std::uint64_t expected, const void* data, std::size_t size,
                   LcmRecord* out, int max_array_length) {
  LcmRecord& record = *out;
  const auto* p = static_cast<const unsigned char*>(data);
  std::size_t pos = 0;
  // what: the part's name, built only when the message is short (not on every field of every message).
  auto need = [&](std::size_t bytes, auto&& what) {
    if (bytes > size - pos) {
      throw LcmDecodeError("truncated: " + std::string(what()) + " needs " + std::to_string(bytes) + " bytes, " +
                           std::to_string(size - pos) + " left of " + std::to_string(size));
    }
  };
  if (data == nullptr) throw LcmDecodeError("no data");
  need(8, [] { return "the fingerprint"; });
  const std::uint64_t fingerprint = ReadBigEndian(p, 8);
  pos = 8;
  if (fingerprint != expected) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "wrong fingerprint 0x%016llx (expected 0x%016llx for %s)",
                  static_cast<unsigned long long>(fingerprint), static_cast<unsigned long long>(expected),
                  layout.type_name.empty() ? "this layout" : layout.type_name.c_str());
    throw LcmDecodeError(buf);
  }
  for (const LcmField& f : layout.fields) {
    long long count = 1;
    if (f.length >= 0) {
      count = f.length;
    } else if (!f.length_field.empty()) {
      const double n = record.numbers.at(f.length_field)[0];
      if (n < 0 || n > max_array_length) {
        throw LcmDecodeError("field '" + f.name + "': length " + f.length_field + " = " +
                             std::to_string(static_cast<long long>(n)) + " is outside [0, " +
                             std::to_string(max_array_length) + "]");
      }
      count = static_cast<long long>(n);
    }
    if (count > max_array_length) {
      throw LcmDecodeError("field '" + f.name + "': " + std::to_string(count) + " elements, more than " +
                           std::to_string(max_array_length));
    }
    if (f.type == LcmType::kString) {
      std::vector<std::string>& out = record.strings[f.name];
      out.resize(static_cast<std::size_t>(count));  // assigned in place: a string keeps its capacity
      for (long long i = 0; i < count; ++i) {
        need(4, [&] { return "the length of string '" + f.name + "'"; });
        const std::uint32_t length = static_cast<std::uint32_t>(ReadBigEndian(p + pos, 4));
        pos += 4;
        if (length == 0) throw LcmDecodeError("string '" + f.name + "': length 0 (no terminator)");
        need(length, [&] { return "string '" + f.name + "'"; });
        if (p[pos + length - 1] != 0) throw LcmDecodeError("string '" + f.name + "' is not terminated");
        out[static_cast<std::size_t>(i)].assign(reinterpret_cast<const char*>(p + pos), length - 1);
        pos += length;
      }
    } else {
      const std::size_t element = ElementSize(f.type);
      need(element * static_cast<std::size_t>(count), [&] { return "field '" + f.name + "'"; });
      std::vector<double>& out = record.numbers[f.name];
      out.clear();
      out.reserve(static_cast<std::size_t>(count));
      for (long long i = 0; i < count; ++i) {
        out.push_back(ReadNumber(p + pos, f.type));
        pos += element;
      }
    }
  }
  if (pos != size) throw LcmDecodeError(std::to_string(size - pos) + " bytes left over after the last field");
}

}  // namespace inertial
