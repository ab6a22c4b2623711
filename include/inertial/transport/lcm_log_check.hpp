/// @file lcm_log_check.hpp
/// The structure of an LCM log file checked before liblcm reads it.
///
/// liblcm's event reader (lcm_eventlog_read_next_event) trusts each event header: a data length of
/// 0x7fffffff makes it allocate a negative size and read into NULL. An lcm-logger file is a
/// sequence of events, each a 28-byte big-endian header (sync word 0xEDA1DA01, event number int64,
/// timestamp int64 [us], channel length int32, data length int32) followed by the channel name and
/// the data (LCM's log file format, lcm-proj.github.io/lcm). Every header is checked against the
/// bytes left in the file before any event is decoded.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace inertial {

/// What the check saw.
struct LcmLogSummary {
  std::int64_t events = 0;
  std::int64_t bytes = 0;
};

/// Longest channel name an event may carry: LCM's own limit for channel names is 63 bytes; a log
/// written by another tool may carry longer ones, but never this long.
inline constexpr std::int32_t kMaxLcmLogChannel = 1 << 16;

/// LCM's limit on channel names (LCM_MAX_CHANNEL_NAME_LENGTH): liblcm neither sends nor receives on
/// a longer name, so a daemon told to listen on one would wait forever.
inline constexpr std::size_t kMaxLcmChannelName = 63;

/// @throws std::invalid_argument naming `what` (e.g. "--channel") unless 1 <= size <= 63 bytes.
void CheckLcmChannelName(const std::string& channel, const std::string& what);

/// Walks every event header of the log at `path`.
/// @throws std::runtime_error naming the file, the event number (counting from 1) and its byte
/// offset: cannot open, a bad sync word, a channel length outside [1, kMaxLcmLogChannel], a
/// negative data length, or a channel or data longer than the bytes left (a truncated log).
LcmLogSummary CheckLcmLog(const std::string& path);

}  // namespace inertial
