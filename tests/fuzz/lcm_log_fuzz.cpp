// Fuzz harness: an LCM log file (lcm-logger's format) as `inertial replay --log` reads it: every
// event header checked (lcm_log_check.hpp) before liblcm reads the file, then the joint_state_t
// events of the default channel through the leg's online estimator, which must stay consistent.
#include <cstdio>
#include <fstream>

#include "fuzz_support.hpp"
#include "inertial/runtime/log_replay.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace inertial;
  const std::string path = fuzz::TempPath("lcm");
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  OnlineJointEstimator e(fuzz::LegDynamics(), Eigen::VectorXd::Zero(fuzz::LegDynamics().num_parameters()));
  try {
    ReplayLog(path, &e, ReplayOptions());
  } catch (const std::runtime_error&) {
  }
  std::remove(path.c_str());
  fuzz::RequireConsistent(e, "an LCM log");
  return 0;
}
