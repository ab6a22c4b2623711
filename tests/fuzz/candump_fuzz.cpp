// Fuzz harness: candump -l logs (can_frame.hpp), line by line as the parser sees them (the whole
// input, up to fuzz.sh's 1 MiB), and as `inertial replay --candump` replays them through the leg's
// motors (mini_cheetah, ids 1-3) and the online estimator, which must stay consistent. The replay
// gets the first 16 KiB (about 500 frames): every frame costs an estimator update, and a megabyte of
// frames (0.5 s under the sanitizers) would leave a run of 10^6 inputs days long, while what a long
// log adds beyond that (more of the same updates) the estimator's own tests cover.
#include <fstream>
#include <sstream>

#include "fuzz_support.hpp"
#include "inertial/config/motors_yaml.hpp"
#include "inertial/transport/can_frame.hpp"
#include "inertial/runtime/log_replay.hpp"
#include "inertial/transport/motor_codec.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace inertial;
  const std::string text = fuzz::Text(data, size);
  std::istringstream lines(text);
  std::string line;
  while (std::getline(lines, line)) {
    CanFrame frame;
    std::string interface, why;
    try {
      if (ParseCandumpLine(line, &frame, &interface, &why) == CandumpLine::kFrame) {
        if (!frame.error && (frame.extended ? frame.id > 0x1FFFFFFFu : frame.id > 0x7FFu)) fuzz::Fail("an identifier out of range");
        if (frame.length > (frame.fd ? 64 : 8)) fuzz::Fail("a payload longer than the frame allows");
      }
    } catch (const std::invalid_argument&) {
    }
  }
  static const CanConfig leg = ParseCanConfig(
      "motors:\n  - {id: 1, joint: abad}\n  - {id: 2, joint: hip}\n  - {id: 3, joint: knee}\n", "leg.yaml");
  const std::string path = fuzz::TempPath("candump");
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out << text.substr(0, 16384);
  }
  OnlineJointEstimator e(fuzz::LegDynamics(), Eigen::VectorXd::Zero(fuzz::LegDynamics().num_parameters()));
  ReplayOptions options;
  options.can = leg;
  try {
    ReplayLog(path, &e, options);
  } catch (const std::runtime_error&) {
  }
  std::remove(path.c_str());
  fuzz::RequireConsistent(e, "a candump log");
  return 0;
}
