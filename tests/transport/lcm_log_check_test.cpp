#include "inertial/transport/lcm_log_check.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <lcm/lcm-cpp.hpp>
#include <string>

#include <unistd.h>

#include "test_support.hpp"

namespace inertial {
namespace {

std::string Temp(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("inertial_lcm_check_" + std::to_string(::getpid()) + "_" + name)).string();
}

void Append(std::string* bytes, std::uint64_t v, int n) {
  for (int i = n - 1; i >= 0; --i) bytes->push_back(static_cast<char>((v >> (8 * i)) & 0xff));
}

// One event as LCM's log format lays it out (big-endian header, channel, data).
std::string Event(std::uint64_t number, const std::string& channel, const std::string& data, std::int64_t claimed_data = -1,
                  std::uint32_t sync = 0xEDA1DA01u) {
  std::string e;
  Append(&e, sync, 4);
  Append(&e, number, 8);
  Append(&e, 1000000 + number, 8);
  Append(&e, channel.size(), 4);
  Append(&e, claimed_data >= 0 ? static_cast<std::uint64_t>(claimed_data) : data.size(), 4);
  return e + channel + data;
}

std::string Write(const std::string& name, const std::string& bytes) {
  const std::string path = Temp(name);
  std::ofstream(path, std::ios::binary) << bytes;
  return path;
}

std::string ErrorOf(const std::string& path) {
  try {
    CheckLcmLog(path);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "no error";
}

// A log written by liblcm itself passes, with its event count (an independent writer).
TEST(LcmLogCheck, LogsWrittenByLcmPass) {
  const std::string path = Temp("lcm.log");
  {
    lcm::LogFile log(path, "w");
    for (int i = 0; i < 5; ++i) {
      lcm::LogEvent ev;
      ev.eventnum = i;
      ev.timestamp = 1000 * i;
      ev.channel = "JOINT_STATE";
      std::string data(37 * i, 'x');
      ev.datalen = static_cast<int32_t>(data.size());
      ev.data = data.data();
      log.writeEvent(&ev);
    }
  }
  const LcmLogSummary s = CheckLcmLog(path);
  EXPECT_EQ(s.events, 5);
  EXPECT_EQ(s.bytes, static_cast<std::int64_t>(std::filesystem::file_size(path)));
  EXPECT_EQ(CheckLcmLog(Write("empty.log", "")).events, 0);
  std::filesystem::remove(path);
}

// The inputs that crashed liblcm or would mislead it: each refused naming the event and offset.
TEST(LcmLogCheck, BadHeadersAreRefusedWithTheEventAndOffset) {
  const std::string good = Event(0, "A", "abcd");
  const std::int64_t second = static_cast<std::int64_t>(good.size());
  struct Case {
    std::string name, bytes, expected;
  };
  const Case cases[] = {
      {"huge.log", good + Event(1, "A", "xy", 0x7fffffff), "event 2 at byte offset " + std::to_string(second)},
      {"huge2.log", good + Event(1, "A", "xy", 0x7fffffff), "2147483647 data bytes but only"},
      {"negative.log", good + Event(1, "A", "xy", 0x80000000u), "negative data length"},
      {"sync.log", good + Event(1, "A", "xy", -1, 0x12345678u), "no LCM sync word"},
      {"truncated.log", good + Event(1, "A", "xyz").substr(0, 30), "(a truncated or corrupt log)"},
      {"short.log", good + std::string(10, '\0'), "only 10 bytes left"},
      {"nochannel.log", Event(0, "", "abc"), "channel name of 0 bytes"},
      {"text.log", "t,q_hip,tau_hip\n0,1,2\n0.1,1,2\n0.2,1,2\n", "event 1 at byte offset 0"},
  };
  for (const Case& c : cases) {
    const std::string path = Write(c.name, c.bytes);
    const std::string message = ErrorOf(path);
    EXPECT_NE(message.find(path), std::string::npos) << message;
    EXPECT_NE(message.find(c.expected), std::string::npos) << c.name << ": " << message;
    std::filesystem::remove(path);
  }
  EXPECT_NE(ErrorOf("/nonexistent/x.log").find("cannot read the LCM log '/nonexistent/x.log': No such file or directory"), std::string::npos);
}

TEST(LcmChannelName, LcmsLimitIsEnforcedNamingTheOption) {
  EXPECT_NO_THROW(CheckLcmChannelName(std::string(63, 'A'), "--channel"));
  auto message = [](const std::string& channel) {
    try {
      CheckLcmChannelName(channel, "--channel");
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message(std::string(64, 'A')).find("--channel: the LCM channel name has 64 bytes"), std::string::npos);
  EXPECT_NE(message(std::string(121 * 1024, 'A')).find("at most 63"), std::string::npos);
  EXPECT_NE(message("").find("empty"), std::string::npos);
}

}  // namespace
}  // namespace inertial
