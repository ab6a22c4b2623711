#include "inertial/transport/can_frame.hpp"

#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace inertial {
namespace {

constexpr std::uint32_t kErrorFlag = 0x20000000u;  // CAN_ERR_FLAG of linux/can.h

int HexValue(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

std::string_view Trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r' || s.back() == '\n')) s.remove_suffix(1);
  return s;
}

}  // namespace

bool IsValidFdLength(int n) {
  return (n >= 0 && n <= 8) || n == 12 || n == 16 || n == 20 || n == 24 || n == 32 || n == 48 || n == 64;
}

namespace {

// Reads a candump time stamp, seconds.micros of digits only, into its whole seconds and its
// fraction; returns why it is not one (a kNotAFrame reason), or nullptr.
const char* ParseTimeStamp(std::string_view stamp, double* seconds, double* fraction) {
  const size_t dot = stamp.find('.');
  if (dot == std::string_view::npos || dot == 0 || dot + 1 >= stamp.size()) return "time stamp is not seconds.micros";
  double scale = 0.1;
  for (size_t i = 0; i < stamp.size(); ++i) {
    if (i == dot) continue;
    if (stamp[i] < '0' || stamp[i] > '9') return "time stamp is not seconds.micros";
    if (i < dot) {
      *seconds = 10.0 * *seconds + (stamp[i] - '0');
    } else {
      *fraction += scale * (stamp[i] - '0');
      scale *= 0.1;
    }
  }
  if (!(*seconds < 1e12)) return "time stamp out of range";
  return nullptr;
}

// Reads the identifier (3 hex digits for 11 bits, 8 for 29 bits or an error frame's class) into
// out's id, extended and error; throws, prefixed by where, if it is malformed or out of range.
void ParseIdentifier(std::string_view id_text, const std::string& where, CanFrame* out) {
  if (id_text.size() != 3 && id_text.size() != 8) {
    throw std::invalid_argument(where + "the identifier must have 3 (11-bit) or 8 (29-bit) hex digits");
  }
  std::uint32_t id = 0;
  for (char c : id_text) {
    const int v = HexValue(c);
    if (v < 0) throw std::invalid_argument(where + "the identifier is not hexadecimal");
    id = (id << 4) | static_cast<std::uint32_t>(v);
  }
  out->extended = id_text.size() == 8;
  if (out->extended && (id & kErrorFlag) != 0) {  // an error frame: id holds the error class
    out->error = true;
    out->extended = false;
    id &= ~kErrorFlag;
  }
  if (out->extended || out->error) {
    if (id > 0x1FFFFFFFu) throw std::invalid_argument(where + "the identifier exceeds 29 bits");
  } else if (id > 0x7FFu) {
    throw std::invalid_argument(where + "an 11-bit identifier above 0x7FF");
  }
  out->id = id;
}

// Reads the data bytes (hex digit pairs, '.' allowed between bytes, at most max_length of them)
// into out's data and length; throws, prefixed by where, if they are malformed.
void ParseDataBytes(std::string_view data, int max_length, const std::string& where, CanFrame* out) {
  int n = 0;
  int high = -1;
  for (char c : data) {
    if (c == '.') {
      if (high >= 0) throw std::invalid_argument(where + "a '.' inside a byte");
      continue;
    }
    const int v = HexValue(c);
    if (v < 0) throw std::invalid_argument(where + "the data are not hexadecimal");
    if (high < 0) {
      high = v;
    } else {
      if (n >= max_length) {
        throw std::invalid_argument(where + "more than " + std::to_string(max_length) + " data bytes");
      }
      out->data[static_cast<size_t>(n++)] = static_cast<std::uint8_t>((high << 4) | v);
      high = -1;
    }
  }
  if (high >= 0) throw std::invalid_argument(where + "an odd number of hex digits");
  if (out->fd && !IsValidFdLength(n)) throw std::invalid_argument(where + std::to_string(n) + " bytes is not a CAN FD length");
  out->length = static_cast<std::uint8_t>(n);
}

}  // namespace

CandumpLine ParseCandumpLine(std::string_view line, CanFrame* f, std::string* iface, std::string* why) {
  auto not_frame = [&](const char* reason) {
    if (why) *why = reason;
    return CandumpLine::kNotAFrame;
  };
  line = Trim(line);
  if (line.empty()) return not_frame("blank line");
  if (line.front() != '(') return not_frame("does not start with '(' and a time stamp");
  const size_t close = line.find(')');
  if (close == std::string_view::npos) return not_frame("no ')' after the time stamp");
  double seconds = 0.0, fraction = 0.0;
  if (const char* reason = ParseTimeStamp(line.substr(1, close - 1), &seconds, &fraction)) return not_frame(reason);
  std::string_view rest = Trim(line.substr(close + 1));
  const size_t space = rest.find_first_of(" \t");
  if (space == std::string_view::npos) return not_frame("no interface and frame after the time stamp");
  const std::string_view name = rest.substr(0, space);
  std::string_view frame = Trim(rest.substr(space));
  // A trailing direction marker (can-utils' -x: " R" received, " T" transmitted).
  const size_t marker = frame.find_first_of(" \t");
  if (marker != std::string_view::npos) {
    const std::string_view tail = Trim(frame.substr(marker));
    if (tail != "R" && tail != "T") return not_frame("unexpected text after the frame");
    frame = frame.substr(0, marker);
  }
  const size_t hash = frame.find('#');
  if (hash == std::string_view::npos) return not_frame("no '#' between identifier and data");
  const std::string where = "candump frame '" + std::string(frame) + "': ";
  CanFrame out;
  ParseIdentifier(frame.substr(0, hash), where, &out);
  out.t = seconds + fraction;
  std::string_view data = frame.substr(hash + 1);
  int max_length = 8;
  if (!data.empty() && data.front() == '#') {  // CAN FD: ##<flags><data>
    out.fd = true;
    max_length = 64;
    data.remove_prefix(1);
    if (data.empty() || HexValue(data.front()) < 0) throw std::invalid_argument(where + "CAN FD frame without a flags digit");
    out.fd_flags = static_cast<std::uint8_t>(HexValue(data.front()));
    data.remove_prefix(1);
  } else if (!data.empty() && (data.front() == 'R' || data.front() == 'r')) {
    out.remote = true;
    data.remove_prefix(1);
    if (data.size() > 1 || (data.size() == 1 && (data.front() < '0' || data.front() > '8'))) {
      throw std::invalid_argument(where + "a remote frame's length must be one digit 0-8");
    }
    out.length = data.empty() ? 0 : static_cast<std::uint8_t>(data.front() - '0');
    *f = out;
    if (iface) *iface = std::string(name);
    return CandumpLine::kFrame;
  }
  ParseDataBytes(data, max_length, where, &out);
  *f = out;
  if (iface) *iface = std::string(name);
  return CandumpLine::kFrame;
}

std::string FormatCandumpLine(const CanFrame& f, const std::string& iface) {
  char buf[64];
  const double whole = std::floor(f.t);
  long long micros = std::llround((f.t - whole) * 1e6);
  long long secs = static_cast<long long>(whole);
  if (micros >= 1000000) {
    micros -= 1000000;
    ++secs;
  }
  std::snprintf(buf, sizeof buf, "(%010lld.%06lld) ", secs, micros);
  std::string out = buf;
  out += iface + " ";
  const std::uint32_t id = f.error ? (f.id | kErrorFlag) : f.id;
  std::snprintf(buf, sizeof buf, (f.extended || f.error) ? "%08X" : "%03X", id);
  out += buf;
  out += '#';
  if (f.remote) {
    out += 'R';
    if (f.length > 0) out += static_cast<char>('0' + f.length);
    return out;
  }
  if (f.fd) {
    out += '#';
    std::snprintf(buf, sizeof buf, "%X", f.fd_flags & 0xF);
    out += buf;
  }
  for (int i = 0; i < f.length; ++i) {
    std::snprintf(buf, sizeof buf, "%02X", f.data[static_cast<size_t>(i)]);
    out += buf;
  }
  return out;
}

}  // namespace inertial
