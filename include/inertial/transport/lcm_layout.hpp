/// @file lcm_layout.hpp
/// LCM messages decoded without trusting them. A layout lists a message type's fields as its .lcm
/// file does (name, primitive type, at most one array dimension: a fixed length or the name of an
/// earlier integer field); from it follow the type's fingerprint (the 8-byte hash every encoded
/// LCM message starts with, computed as lcm-gen does: LCM's type-specification hash of member
/// names, types and dimensions, rotated left by one bit for a type without nested structs) and a
/// decoder that checks everything before it allocates: the fingerprint, every length against the
/// bytes left and against a cap, string terminators, and that no byte is left over.
///
/// This serves the project's own types (their layouts are in lcm_messages.hpp and tested against
/// lcm-gen's getHash()) and a user's existing message types, described in a config file
/// (config/message_format.hpp), so that users need not change their controller.
/// Encoding is big-endian, as LCM's.
#pragma once

#include <cstdint>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace inertial {

enum class LcmType { kInt8, kInt16, kInt32, kInt64, kByte, kFloat, kDouble, kString, kBoolean };

/// "int8_t", "int16_t", "int32_t", "int64_t", "byte", "float", "double", "string", "boolean".
const char* ToString(LcmType type);

struct LcmField {
  std::string name;
  LcmType type = LcmType::kDouble;
  /// Scalar when both are unset; else an array of `length` (fixed) or of the value of the earlier
  /// integer field `length_field`.
  int length = -1;
  std::string length_field;
  bool is_array() const { return length >= 0 || !length_field.empty(); }
};

struct LcmLayout {
  std::string type_name;  ///< for messages only (not part of the fingerprint)
  std::vector<LcmField> fields;
};

/// A message that does not decode: the reason names the field and what is wrong.
struct LcmDecodeError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// The decoded fields: numbers (integers, booleans and reals as doubles) or strings, by name; a
/// scalar is an array of one.
struct LcmRecord {
  std::map<std::string, std::vector<double>> numbers;
  std::map<std::string, std::vector<std::string>> strings;
  /// The values of a numeric field. @throws LcmDecodeError if there is none of that name.
  const std::vector<double>& Numbers(const std::string& field) const;
  const std::vector<std::string>& Strings(const std::string& field) const;
};

/// The fingerprint as it appears on the wire (the first 8 bytes of every message).
/// @throws std::invalid_argument if the layout is invalid (CheckLcmLayout).
std::uint64_t LcmFingerprint(const LcmLayout& layout);

/// Checks the layout: unique non-empty names, a length field that is an earlier scalar integer.
/// @throws std::invalid_argument naming the field.
void CheckLcmLayout(const LcmLayout& layout);

/// Decodes one message (fingerprint first). Arrays longer than max_array_length are refused.
/// @throws LcmDecodeError.
LcmRecord DecodeLcm(const LcmLayout& layout, const void* data, std::size_t size, int max_array_length = 4096);

/// The same for a stream of messages: the layout's fingerprint computed once by the caller
/// (LcmFingerprint, which also checks the layout: this function does not, and a layout that was
/// never checked may throw other than LcmDecodeError) and *record reused, every field of the layout
/// overwritten in place (its vectors and strings keep their capacity), so that a decoder of a
/// fixed layout allocates nothing per message once the arrays and names have reached their size.
/// After a throw *record holds a partial message.
/// @throws LcmDecodeError.
void DecodeLcmInto(const LcmLayout& layout, std::uint64_t fingerprint, const void* data, std::size_t size,
                   LcmRecord* record, int max_array_length = 4096);

}  // namespace inertial
