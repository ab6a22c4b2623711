#include "inertial/transport/lcm_log_check.hpp"
#include "inertial/formats/file_error.hpp"

#include <array>
#include <fstream>
#include <stdexcept>

namespace inertial {
namespace {

constexpr std::uint32_t kSyncWord = 0xEDA1DA01u;
constexpr std::int64_t kHeaderBytes = 28;

std::uint64_t BigEndian(const unsigned char* p, int bytes) {
  std::uint64_t v = 0;
  for (int i = 0; i < bytes; ++i) v = (v << 8) | p[i];
  return v;
}

}  // namespace

void CheckLcmChannelName(const std::string& channel, const std::string& what) {
  if (channel.empty()) throw std::invalid_argument(what + ": the LCM channel name is empty");
  if (channel.size() > kMaxLcmChannelName) {
    throw std::invalid_argument(what + ": the LCM channel name has " + std::to_string(channel.size()) +
                                " bytes; LCM carries at most " + std::to_string(kMaxLcmChannelName));
  }
}

LcmLogSummary CheckLcmLog(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(CannotText("read", "LCM log", path));
  in.seekg(0, std::ios::end);
  const std::int64_t size = static_cast<std::int64_t>(in.tellg());
  in.seekg(0, std::ios::beg);
  LcmLogSummary summary;
  summary.bytes = size;
  std::int64_t offset = 0;
  while (offset < size) {
    const std::int64_t event = summary.events + 1;
    auto fail = [&](const std::string& what) {
      throw std::runtime_error("'" + path + "': LCM event " + std::to_string(event) + " at byte offset " +
                               std::to_string(offset) + ": " + what);
    };
    if (size - offset < kHeaderBytes) {
      fail("only " + std::to_string(size - offset) + " bytes left for a 28-byte event header (a truncated log)");
    }
    std::array<unsigned char, kHeaderBytes> h{};
    // Sequential reads and ignore() (buffered): no seek, so no system call per event.
    if (!in.read(reinterpret_cast<char*>(h.data()), kHeaderBytes)) fail("cannot read the event header");
    const std::uint32_t sync = static_cast<std::uint32_t>(BigEndian(h.data(), 4));
    if (sync != kSyncWord) fail("no LCM sync word (not an lcm-logger log, or corrupt)");
    const std::int32_t channel = static_cast<std::int32_t>(static_cast<std::uint32_t>(BigEndian(h.data() + 20, 4)));
    const std::int32_t data = static_cast<std::int32_t>(static_cast<std::uint32_t>(BigEndian(h.data() + 24, 4)));
    if (channel < 1 || channel > kMaxLcmLogChannel) {
      fail("the header claims a channel name of " + std::to_string(channel) + " bytes (1 to " +
           std::to_string(kMaxLcmLogChannel) + " expected)");
    }
    if (data < 0) fail("the header claims a negative data length (" + std::to_string(data) + ")");
    const std::int64_t left = size - offset - kHeaderBytes;
    if (static_cast<std::int64_t>(channel) + data > left) {
      fail("the header claims " + std::to_string(channel) + " channel and " + std::to_string(data) +
           " data bytes but only " + std::to_string(left) + " remain (a truncated or corrupt log)");
    }
    in.ignore(static_cast<std::streamsize>(channel) + data);
    offset += kHeaderBytes + channel + data;
    ++summary.events;
  }
  return summary;
}

}  // namespace inertial
