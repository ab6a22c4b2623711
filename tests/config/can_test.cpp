// CAN: the candump -l format (every case of the format, round trips, a cross-check with can-utils'
// log2long, 10^6 random and mutated lines), motor codecs against frames worked out by hand from the
// protocol description, motors.yaml errors, and the assembly of joint ticks (late, superseded,
// missing motors never filled in), through to the estimator.
#include <gtest/gtest.h>

#include "inertial/estimation/causal_acceleration.hpp"
#include "inertial/estimation/stream_preprocessor.hpp"

#include <fstream>
#include <regex>
#include <sstream>

#include "cli_support.hpp"
#include "inertial/config/motors_yaml.hpp"
#include "inertial/estimation/joint_identification.hpp"
#include "inertial/transport/can_joint_assembler.hpp"
#include "inertial/formats/model_file.hpp"
#include "simulated_robot.hpp"

namespace inertial {
namespace {

namespace fs = std::filesystem;

CanFrame Parse(const std::string& line, std::string* iface = nullptr) {
  CanFrame f;
  std::string name;
  EXPECT_EQ(ParseCandumpLine(line, &f, &name), CandumpLine::kFrame) << line;
  if (iface) *iface = name;
  return f;
}

TEST(Candump, EveryCaseOfTheFormat) {
  std::string iface;
  CanFrame f = Parse("(1436509052.249713) vcan0 123#DEADBEEF", &iface);
  EXPECT_EQ(iface, "vcan0");
  EXPECT_NEAR(f.t, 1436509052.249713, 1e-6);
  EXPECT_EQ(f.id, 0x123u);
  EXPECT_FALSE(f.extended);
  ASSERT_EQ(f.length, 4);
  EXPECT_EQ(f.data[0], 0xDE);
  EXPECT_EQ(f.data[3], 0xEF);
  f = Parse("(0.000001) can1 1F334455#11.22.33");  // extended, '.' separators
  EXPECT_TRUE(f.extended);
  EXPECT_EQ(f.id, 0x1F334455u);
  EXPECT_EQ(f.length, 3);
  EXPECT_EQ(f.data[2], 0x33);
  f = Parse("(1.5) can0 321#R");
  EXPECT_TRUE(f.remote);
  EXPECT_EQ(f.length, 0);
  f = Parse("(1.5) can0 321#R5");
  EXPECT_TRUE(f.remote);
  EXPECT_EQ(f.length, 5);
  f = Parse("(2.000000) can0 123##10123456789ABCDEF");  // FD, flags 1 (bit-rate switch), 8 bytes
  EXPECT_TRUE(f.fd);
  EXPECT_EQ(f.fd_flags, 1);
  EXPECT_EQ(f.length, 8);
  EXPECT_EQ(f.data[7], 0xEF);
  f = Parse("(2.0) can0 123##2" + std::string(24, 'A'));  // FD, 12 bytes, ESI
  EXPECT_EQ(f.length, 12);
  EXPECT_EQ(f.fd_flags, 2);
  f = Parse("(3.0) can0 20000004#0004000000000000");  // an error frame (controller problem)
  EXPECT_TRUE(f.error);
  EXPECT_EQ(f.id, 0x4u);
  EXPECT_EQ(f.length, 8);
  f = Parse("(4.0) can0 123#00 R");  // direction markers
  EXPECT_EQ(f.length, 1);
  f = Parse("(4.0) can0 123#0102 T");
  EXPECT_EQ(f.length, 2);
  f = Parse("(5.0) can0 7FF#");  // no data
  EXPECT_EQ(f.length, 0);
  std::string why;
  const std::string huge_time = "(" + std::string(400, '9') + ".0) can0 123#00";
  for (const std::string& not_frame : {std::string(""), std::string("   "), std::string("# a comment"),
                                       std::string("Timestamp: 1.0 ID: 123"), std::string("(1.0)"),
                                       std::string("(abc) can0 123#00"), std::string("(1.0) can0 123#00 X"), huge_time}) {
    EXPECT_EQ(ParseCandumpLine(not_frame, &f, &iface, &why), CandumpLine::kNotAFrame) << not_frame;
  }
  for (const char* bad : {"(1.0) can0 800#00", "(1.0) can0 12#00", "(1.0) can0 123#0", "(1.0) can0 123#GG",
                          "(1.0) can0 123#010203040506070809", "(1.0) can0 123##1010203040506070809",
                          "(1.0) can0 123#R9", "(1.0) can0 3FFFFFFFF#00", "(1.0) can0 123#0.1"}) {
    EXPECT_THROW(ParseCandumpLine(bad, &f, &iface, &why), std::invalid_argument) << bad;
  }
}

CanFrame RandomFrame(testing::Rng& rng) {
  CanFrame f;
  f.t = std::floor(rng.Uniform(0, 2e9)) + std::floor(rng.Uniform(0, 1e6)) * 1e-6;
  const double kind = rng.Uniform(0, 1);
  f.extended = kind < 0.4;
  f.id = static_cast<std::uint32_t>(rng.Uniform(0, f.extended ? 0x1FFFFFFF : 0x7FF));
  if (kind < 0.1) {
    f.remote = true;
    f.length = static_cast<std::uint8_t>(rng.Uniform(0, 9));
  } else if (kind < 0.2) {
    f.error = true;
    f.extended = false;
    f.length = 8;
  } else if (kind < 0.35) {
    f.fd = true;
    f.fd_flags = static_cast<std::uint8_t>(rng.Uniform(0, 4));
    const int sizes[] = {0, 5, 8, 12, 16, 20, 24, 32, 48, 64};
    f.length = static_cast<std::uint8_t>(sizes[static_cast<int>(rng.Uniform(0, 10))]);
  } else {
    f.length = static_cast<std::uint8_t>(rng.Uniform(0, 9));
  }
  if (!f.remote) {
    for (int i = 0; i < f.length; ++i) f.data[static_cast<size_t>(i)] = static_cast<std::uint8_t>(rng.Uniform(0, 256));
  }
  return f;
}

bool Same(const CanFrame& a, const CanFrame& b) {
  return std::abs(a.t - b.t) < 1e-6 && a.id == b.id && a.extended == b.extended && a.remote == b.remote &&
         a.error == b.error && a.fd == b.fd && (!a.fd || a.fd_flags == b.fd_flags) && a.length == b.length &&
         (a.remote || std::equal(a.data.begin(), a.data.begin() + a.length, b.data.begin()));
}

TEST(Candump, RoundTripsAndAgreesWithLog2longAndLog2asc) {
  testing::Rng rng(1);
  const fs::path log = testing::UniqueTempPath("round.log");
  std::vector<CanFrame> frames;
  {
    std::ofstream out(log);
    for (int i = 0; i < 2000; ++i) {
      CanFrame f = RandomFrame(rng);
      if (f.fd || f.error) continue;  // log2long of can-utils 2020.11 prints classic frames
      f.t = 1000.0 + 0.001 * i;       // a log's times increase (log2asc restarts at a backward jump)
      frames.push_back(f);
      out << FormatCandumpLine(f, "can0") << "\n";
      CanFrame back;
      std::string iface;
      ASSERT_EQ(ParseCandumpLine(FormatCandumpLine(f, "can0"), &back, &iface), CandumpLine::kFrame);
      ASSERT_TRUE(Same(f, back)) << FormatCandumpLine(f, "can0");
    }
  }
  for (int i = 0; i < 2000; ++i) {  // FD and error frames round-trip too
    CanFrame f = RandomFrame(rng), back;
    std::string iface;
    ASSERT_EQ(ParseCandumpLine(FormatCandumpLine(f, "vcan1"), &back, &iface), CandumpLine::kFrame);
    ASSERT_TRUE(Same(f, back)) << FormatCandumpLine(f, "vcan1");
  }
  // can-utils' log2long reads the same file: its identifier, length and bytes are ours.
  if (!fs::exists("/usr/bin/log2long")) GTEST_SKIP() << "can-utils' log2long is not installed";
  const testing::CliRun r = testing::RunProgram("/usr/bin/log2long", {}, testing::ReadFile(log));
  ASSERT_EQ(r.exit_code, 0) << testing::Describe(r);
  std::istringstream lines(r.out);
  std::string line;
  size_t k = 0;
  const std::regex pattern(R"(^\(([0-9.]+)\)\s+can0\s+([0-9A-F]+)\s+\[(\d)\]\s*((?:[0-9A-F]{2} )*|remote request))");
  while (std::getline(lines, line) && k < frames.size()) {
    std::smatch m;
    ASSERT_TRUE(std::regex_search(line, m, pattern)) << line;
    const CanFrame& f = frames[k++];
    EXPECT_EQ(std::stoul(m[2].str(), nullptr, 16), f.id) << line;
    EXPECT_EQ(std::stoi(m[3].str()), f.length) << line;
    if (!f.remote) {
      std::string bytes;
      char buf[4];
      for (int i = 0; i < f.length; ++i) {
        std::snprintf(buf, sizeof buf, "%02X ", f.data[static_cast<size_t>(i)]);
        bytes += buf;
      }
      EXPECT_EQ(m[4].str(), bytes) << line;
    }
  }
  EXPECT_EQ(k, frames.size());
  // And can-utils' log2asc (Vector ASC): identifier with 'x' when extended, 'd' data or 'r' remote,
  // length and bytes.
  if (!fs::exists("/usr/bin/log2asc")) GTEST_SKIP() << "can-utils' log2asc is not installed";
  const testing::CliRun asc = testing::RunProgram("/usr/bin/log2asc", {"-I", log.string(), "can0"});
  ASSERT_EQ(asc.exit_code, 0) << testing::Describe(asc);
  std::istringstream asc_lines(asc.out);
  const std::regex asc_pattern(R"(^\s+[0-9.]+ 1\s+([0-9A-F]+)(x?)\s+Rx\s+([dr]) (\d+)((?: [0-9A-F]{2})*)\s*$)");
  k = 0;
  while (std::getline(asc_lines, line)) {
    std::smatch m;
    if (!std::regex_search(line, m, asc_pattern)) continue;  // headers: date, base, ...
    ASSERT_LT(k, frames.size()) << line;
    const CanFrame& f = frames[k++];
    EXPECT_EQ(std::stoul(m[1].str(), nullptr, 16), f.id) << line;
    EXPECT_EQ(m[2].str() == "x", f.extended) << line;
    EXPECT_EQ(m[3].str() == "r", f.remote) << line;
    EXPECT_EQ(std::stoi(m[4].str()), f.length) << line;
    if (!f.remote) {
      std::string bytes;
      char buf[4];
      for (int i = 0; i < f.length; ++i) {
        std::snprintf(buf, sizeof buf, " %02X", f.data[static_cast<size_t>(i)]);
        bytes += buf;
      }
      EXPECT_EQ(m[5].str(), bytes) << line;
    }
  }
  EXPECT_EQ(k, frames.size());
  fs::remove(log);
}

// 10^6 random and mutated lines: never a crash; anything accepted formats and parses back the same.
TEST(Candump, SurvivesAMillionRandomLines) {
  testing::Rng rng(2);
  const std::string alphabet = "0123456789ABCDEFabcdef#.()R T rx\t-:";
  int frames = 0, not_frames = 0, errors = 0;
  for (int i = 0; i < 1000000; ++i) {
    std::string line;
    if (i % 2 == 0) {
      line = FormatCandumpLine(RandomFrame(rng), "can0");
      const int edits = 1 + static_cast<int>(rng.Uniform(0, 3));
      for (int e = 0; e < edits && !line.empty(); ++e) {
        const size_t at = static_cast<size_t>(rng.Uniform(0, static_cast<double>(line.size())));
        line[at] = alphabet[static_cast<size_t>(rng.Uniform(0, static_cast<double>(alphabet.size())))];
      }
    } else {
      const int n = static_cast<int>(rng.Uniform(0, 60));
      line = "(1.0) can0 ";
      for (int c = 0; c < n; ++c) line += alphabet[static_cast<size_t>(rng.Uniform(0, static_cast<double>(alphabet.size())))];
    }
    CanFrame f;
    std::string iface;
    try {
      if (ParseCandumpLine(line, &f, &iface) == CandumpLine::kFrame) {
        ++frames;
        CanFrame back;
        ASSERT_EQ(ParseCandumpLine(FormatCandumpLine(f, iface), &back, &iface), CandumpLine::kFrame) << line;
        ASSERT_TRUE(Same(f, back)) << line;
      } else {
        ++not_frames;
      }
    } catch (const std::invalid_argument&) {
      ++errors;
    }
  }
  EXPECT_GT(frames, 1000);
  EXPECT_GT(not_frames, 1000);
  EXPECT_GT(errors, 1000);
}

MotorConfig MiniCheetah(std::uint32_t id) {
  MotorConfig m;
  m.can_id = id;
  m.joint = "j" + std::to_string(id);
  return m;  // the protocol's usual ranges: p +-12.5 rad, v +-65 rad/s, t +-18 N m
}

// Worked by hand from the protocol: x -> min + x (max - min) / (2^bits - 1).
TEST(MotorCodec, MiniCheetahFramesWorkedByHand) {
  const MotorConfig m = MiniCheetah(1);
  CanFrame f;
  f.id = 1;
  f.length = 6;
  const std::uint8_t middle[6] = {0x01, 0x80, 0x00, 0x80, 0x08, 0x00};  // p 0x8000, v 0x800, t 0x800
  std::copy(middle, middle + 6, f.data.begin());
  MotorReading r;
  ASSERT_EQ(DecodeMotorFrame(m, f, &r), Rejection::kNone);
  EXPECT_DOUBLE_EQ(r.q, -12.5 + 32768.0 * 25.0 / 65535.0);  // 1.907e-4 rad
  EXPECT_DOUBLE_EQ(r.qd, -65.0 + 2048.0 * 130.0 / 4095.0);  // 0.01587 rad/s
  EXPECT_DOUBLE_EQ(r.tau, -18.0 + 2048.0 * 36.0 / 4095.0);  // 0.004396 N m
  const std::uint8_t ends[6] = {0x01, 0x00, 0x00, 0xFF, 0xF0, 0x00};  // p 0 (min), v 0xFFF (max), t 0 (min)
  std::copy(ends, ends + 6, f.data.begin());
  ASSERT_EQ(DecodeMotorFrame(m, f, &r), Rejection::kNone);
  EXPECT_DOUBLE_EQ(r.q, -12.5);
  EXPECT_DOUBLE_EQ(r.qd, 65.0);
  EXPECT_DOUBLE_EQ(r.tau, -18.0);
  // Encoding: the same bytes back, saturation at the range ends.
  MotorReading big{0.0, 20.0, -100.0, 18.0};
  const CanFrame e = EncodeMotorFrame(m, big);
  EXPECT_EQ(e.length, 6);
  EXPECT_EQ(e.data[0], 0x01);
  EXPECT_EQ((e.data[1] << 8) | e.data[2], 0xFFFF);               // +12.5 rad
  EXPECT_EQ((e.data[3] << 4) | (e.data[4] >> 4), 0x000);          // -65 rad/s
  EXPECT_EQ(((e.data[4] & 0xF) << 8) | e.data[5], 0xFFF);         // +18 N m
  // Direction, gear and torque constant: a 6:1 motor-side reading, reversed, current in A.
  MotorConfig geared = m;
  geared.direction = -1;
  geared.gear = 6;
  geared.kt = 0.1;
  std::copy(middle, middle + 6, f.data.begin());
  ASSERT_EQ(DecodeMotorFrame(geared, f, &r), Rejection::kNone);
  EXPECT_DOUBLE_EQ(r.q, -(-12.5 + 32768.0 * 25.0 / 65535.0) / 6.0);
  EXPECT_DOUBLE_EQ(r.tau, -(-18.0 + 2048.0 * 36.0 / 4095.0) * 0.1 * 6.0);
  // Round trips within half a quantization step.
  testing::Rng rng(3);
  for (int i = 0; i < 1000; ++i) {
    const MotorReading in{0.0, rng.Uniform(-2, 2), rng.Uniform(-10, 10), rng.Uniform(-3, 3)};
    ASSERT_EQ(DecodeMotorFrame(geared, EncodeMotorFrame(geared, in), &r), Rejection::kNone);
    EXPECT_NEAR(r.q, in.q, 0.5 * 25.0 / 65535.0 / 6.0 + 1e-12);
    EXPECT_NEAR(r.qd, in.qd, 0.5 * 130.0 / 4095.0 / 6.0 + 1e-12);
    EXPECT_NEAR(r.tau, in.tau, 0.5 * 36.0 / 4095.0 * 0.6 + 1e-12);
  }
  // Malformed: short, wrong motor id in byte 0, remote.
  f.length = 5;
  std::string why;
  EXPECT_EQ(DecodeMotorFrame(m, f, &r, &why), Rejection::kMalformed);
  f.length = 6;
  f.data[0] = 7;
  EXPECT_EQ(DecodeMotorFrame(m, f, &r, &why), Rejection::kMalformed);
  EXPECT_NE(why.find("byte 0"), std::string::npos) << why;
  f.data[0] = 1;
  f.remote = true;
  EXPECT_EQ(DecodeMotorFrame(m, f, &r, &why), Rejection::kMalformed);
}

TEST(MotorCodec, LinearFieldsWorkedByHand) {
  MotorConfig m;
  m.can_id = 0x141;
  m.joint = "knee";
  m.protocol = MotorProtocol::kLinear;
  m.position = {0, 2, true, true, 0.001, 0.0};   // int16 little-endian, mrad
  m.velocity = {2, 2, false, false, 0.01, -5.0};  // uint16 big-endian, 0.01 rad/s, offset -5
  m.torque = {4, 4, true, false, 1e-4, 0.0};     // int32 big-endian
  CanFrame f;
  f.id = 0x141;
  f.length = 8;
  const std::uint8_t bytes[8] = {0x18, 0xFC, 0x01, 0xF4, 0xFF, 0xFF, 0x3C, 0xB0};
  std::copy(bytes, bytes + 8, f.data.begin());
  MotorReading r;
  ASSERT_EQ(DecodeMotorFrame(m, f, &r), Rejection::kNone);
  EXPECT_DOUBLE_EQ(r.q, -1.0);                 // 0xFC18 = -1000 mrad
  EXPECT_DOUBLE_EQ(r.qd, 500 * 0.01 - 5.0);    // 0x01F4 = 500
  EXPECT_NEAR(r.tau, -50000 * 1e-4, 1e-12);    // 0xFFFF3CB0 = -50000
  const CanFrame back = EncodeMotorFrame(m, r);
  EXPECT_TRUE(std::equal(bytes, bytes + 8, back.data.begin()));
}

TEST(CanConfig, ParsesAndRefuses) {
  const CanConfig c = ParseCanConfig(R"(
window: 0.003
motors:
  - {id: 0x001, joint: abad, position: [-12.5, 12.5]}
  - id: 0x141
    joint: knee
    protocol: linear
    position: {byte: 0, width: 2, scale: 0.001}
    velocity: {byte: 2, width: 2, scale: 0.01}
    torque: {byte: 4, width: 2, scale: 0.01, endian: big}
)", "motors.yaml");
  ASSERT_EQ(c.motors.size(), 2u);
  EXPECT_EQ(c.motors[1].can_id, 0x141u);
  EXPECT_FALSE(c.motors[1].torque.little_endian);
  EXPECT_DOUBLE_EQ(c.window, 0.003);
  for (const char* bad : {"motors: []", "motors:\n  - {id: 0x800, joint: a}", "motors:\n  - {id: 1, joint: a, colour: red}",
                          "motors:\n  - {id: 1, joint: a}\n  - {id: 2, joint: a}", "motors:\n  - {id: 1, joint: a, protocol: canopen}",
                          "motors:\n  - {id: 1, joint: a, protocol: linear}", "motors:\n  - {id: x1, joint: a}",
                          "motors:\n  - {id: 1, joint: a, position: [3, 1]}", "motors: [", "speed: 3\nmotors: []",
                          "motors:\n  - {id: [1, 2], joint: a}", "motors:\n  - {id: 1, joint: [a, b]}",
                          "motors:\n  - {id: 1, joint: a, extended: maybe}", "motors:\n  - {id: 1, joint: a, motor_id: 1e20}",
                          "motors:\n  - {id: 1, joint: a, protocol: linear, position: {byte: 60}, velocity: {}, torque: {}}",
                          "motors:\n  - {id: 1, joint: a, protocol: linear, position: {width: 2.5}, velocity: {}, torque: {}}"}) {
    EXPECT_THROW(ParseCanConfig(bad, "bad.yaml"), std::invalid_argument) << bad;
  }
}

CanConfig LegConfig() {
  CanConfig c;
  for (int k = 0; k < 3; ++k) {
    MotorConfig m = MiniCheetah(static_cast<std::uint32_t>(k + 1));
    m.joint = std::vector<std::string>{"abad", "hip", "knee"}[static_cast<size_t>(k)];
    c.motors.push_back(m);
  }
  return c;
}

TEST(CanJointAssembler, TicksLateSupersededAndMissing) {
  CanJointAssembler a(LegConfig(), {"abad", "hip", "knee"});
  JointSample s;
  auto frame = [&](int motor, double t, double q) {
    return EncodeMotorFrame(a.config().motors[static_cast<size_t>(motor)], MotorReading{t, q, 0.1 * q, 0.2 * q});
  };
  // Tick 0 is a sample at once: the assembler only assembles (qdd is the preprocessing stage's).
  EXPECT_FALSE(a.Feed(frame(0, 0.0, 0.1), &s));
  EXPECT_FALSE(a.Feed(frame(1, 0.0001, 0.1), &s));
  ASSERT_TRUE(a.Feed(frame(2, 0.0002, 0.1), &s));
  EXPECT_FALSE(s.has_qdd);
  EXPECT_EQ(s.qdd, Eigen::VectorXd::Zero(3));
  EXPECT_FALSE(a.Feed(frame(0, 0.002, 0.2), &s));
  EXPECT_FALSE(a.Feed(frame(1, 0.0021, 0.2), &s));
  ASSERT_TRUE(a.Feed(frame(2, 0.0022, 0.2), &s));
  EXPECT_DOUBLE_EQ(s.t, 0.0022);
  EXPECT_NEAR(s.q[1], 0.2, 1e-3);
  // The knee goes silent: the others' readings age out (late), nothing is filled in.
  EXPECT_FALSE(a.Feed(frame(0, 0.004, 0.3), &s));
  EXPECT_FALSE(a.Feed(frame(1, 0.0041, 0.3), &s));
  EXPECT_FALSE(a.Feed(frame(0, 0.006, 0.3), &s));  // abad again: its older reading is superseded
  EXPECT_EQ(a.counters()[Rejection::kSuperseded], 1u);
  EXPECT_EQ(a.counters()[Rejection::kLate], 0u);                  // hip's 4.1 ms is within 2 ms of 6 ms
  EXPECT_FALSE(a.Feed(frame(1, 0.0101, 0.3), &s));  // hip again (superseded); abad's 6 ms ages out
  EXPECT_EQ(a.counters()[Rejection::kSuperseded], 2u);
  EXPECT_EQ(a.counters()[Rejection::kLate], 1u);
  EXPECT_EQ(a.counters().accepted, 2u);
  // Unknown identifiers, error frames and malformed frames are counted and ignored.
  CanFrame unknown = frame(0, 0.011, 0.3);
  unknown.id = 0x55;
  EXPECT_FALSE(a.Feed(unknown, &s));
  CanFrame error;
  error.error = true;
  EXPECT_FALSE(a.Feed(error, &s));
  CanFrame shortf = frame(2, 0.011, 0.3);
  shortf.length = 3;
  EXPECT_FALSE(a.Feed(shortf, &s));
  EXPECT_EQ(a.counters()[Rejection::kUnknownId], 1u);
  EXPECT_EQ(a.counters()[Rejection::kErrorFrame], 1u);
  EXPECT_EQ(a.counters()[Rejection::kMalformed], 1u);
  EXPECT_EQ(a.last_rejection(), Rejection::kMalformed);
  EXPECT_THROW(CanJointAssembler(LegConfig(), {"abad", "hip", "knee", "ankle"}), std::invalid_argument);
}

// A simulated leg through its motors' frames (quantized by the protocol, with unknown frames mixed
// in) into the estimator: every tick arrives, and the estimate predicts clean torques of another
// trajectory below the measurement noise.
TEST(CanJointAssembler, SimulatedLegThroughTheMotorsIntoTheEstimator) {
  const RobotModel robot = LoadUrdf(testing::Example("leg3.urdf"));
  const RobotDynamics model = MakeRobotDynamics(robot, {});
  const JointSamples log = testing::SimulateLogs(model, testing::TrueParameters(model, {0.0}, 2), 0.1, 10.0, 3, 500).train;
  CanJointAssembler a(LegConfig(), robot.dof_names);
  OnlineEstimatorOptions o;
  o.measurement_sigma = 0.1;
  OnlineJointEstimator via_can(model, Eigen::VectorXd::Zero(model.num_parameters()), o), exact(model, Eigen::VectorXd::Zero(model.num_parameters()), o);
  JointSample s, e;
  StreamPreprocessor preprocess(3, a.config().accel_cutoff_hz);
  CausalAcceleration reference_acceleration(3, a.config().accel_cutoff_hz);
  for (int i = 0; i < log.size(); ++i) {
    for (int k = 0; k < 3; ++k) {
      MotorReading r{log.t[i] + 1e-4 * k, log.q(i, k), log.qd(i, k), log.tau(i, k)};
      if (a.Feed(EncodeMotorFrame(a.config().motors[static_cast<size_t>(k)], r), &s) &&
          preprocess.Process(&s) == Rejection::kNone) {
        via_can.Update(s);
      }
    }
    if (i % 100 == 0) {
      CanFrame junk;
      junk.id = 0x300;
      junk.length = 2;
      a.Feed(junk, &s);
    }
    // The reference: exact samples, with the same causal accelerations the CAN path must use, so
    // that the comparison isolates the protocol's quantization.
    CopySample(log, i, &e);
    if (reference_acceleration.Update(e.t + 2e-4, e.qd, &e.qdd)) exact.Update(e);
  }
  EXPECT_EQ(a.counters().accepted, static_cast<std::uint64_t>(log.size()));
  EXPECT_EQ(a.counters()[Rejection::kUnknownId], static_cast<std::uint64_t>((log.size() + 99) / 100));
  const testing::SimulatedLogs test = testing::SimulateLogs(model, testing::TrueParameters(model, {0.0}, 2), 0.0, 5.0, 4, 500);
  const double e_can = CompareTorques(PredictJointTorques(model, via_can.estimator().parameters(), test.test_clean), test.test_clean.tau).total_rms;
  const double e_exact = CompareTorques(PredictJointTorques(model, exact.estimator().parameters(), test.test_clean), test.test_clean.tau).total_rms;
  // The 12-bit velocity field quantizes qd in steps of 0.032 rad/s, and its difference over 2 ms
  // makes the causal accelerations noisy: the CAN path converges less far than exact samples do
  // (0.068 against 0.018 N m here) but still predicts clean torques below the 0.1 N m noise.
  EXPECT_LT(e_can, 0.1) << e_can << " vs " << e_exact;
  EXPECT_LT(e_exact, e_can);
}

// 10^6 random frames (any identifier, length, flags and bytes) into the codecs and the assembler:
// never a crash (the sanitizer build runs this too), and every reading that comes out is finite
// and within the configured ranges.
TEST(MotorCodec, SurvivesAMillionRandomFrames) {
  testing::Rng rng(9);
  CanConfig config = LegConfig();
  MotorConfig linear;
  linear.can_id = 0x141;
  linear.joint = "knee";
  linear.protocol = MotorProtocol::kLinear;
  linear.position = {0, 4, true, false, 1e-6, 0.0};
  linear.velocity = {60, 4, false, true, 1e-3, -1.0};
  linear.torque = {7, 1, true, true, 0.5, 0.0};
  config.motors[2] = linear;
  CanJointAssembler a(config, {"abad", "hip", "knee"});
  JointSample s;
  MotorReading r;
  int decoded = 0;
  for (int i = 0; i < 1000000; ++i) {
    CanFrame f = RandomFrame(rng);
    if (i % 3 == 0) f.id = static_cast<std::uint32_t>(rng.Uniform(0, 4)) == 3 ? 0x141 : static_cast<std::uint32_t>(rng.Uniform(1, 4));
    if (i % 5 == 0) f.data[0] = static_cast<std::uint8_t>(f.id & 0xFF);
    f.t = i * 1e-4;
    for (const MotorConfig& m : config.motors) {
      if (DecodeMotorFrame(m, f, &r) == Rejection::kNone) {
        ++decoded;
        ASSERT_TRUE(std::isfinite(r.q) && std::isfinite(r.qd) && std::isfinite(r.tau));
        if (m.protocol == MotorProtocol::kMiniCheetah) {
          ASSERT_LE(std::abs(r.q), 12.5);
          ASSERT_LE(std::abs(r.qd), 65.0);
          ASSERT_LE(std::abs(r.tau), 18.0);
        }
      }
    }
    if (a.Feed(f, &s)) {  // rare from random frames; checked when it happens
      ASSERT_TRUE(s.q.allFinite() && s.qd.allFinite() && s.qdd.allFinite() && s.tau.allFinite());
    }
  }
  EXPECT_GT(decoded, 1000);  // random frames that pass a motor's checks, decoded within its ranges
}

}  // namespace
}  // namespace inertial
