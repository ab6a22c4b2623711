// Fuzz harness: inertiald's --config JSON (estimation_daemon.hpp) as main() reads it: size-checked, parsed, then
// applied to the options; an accepted message format must then build the leg's decoder or be
// refused by name, as the daemon's start does.
#include "fuzz_support.hpp"
#include "inertial/config/daemon_config_file.hpp"
#include "inertial/runtime/estimation_daemon.hpp"
#include "inertial/transport/joint_message.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace inertial;
  DaemonOptions options;
  try {
    ApplyDaemonConfigText(fuzz::Text(data, size), "fuzz.json", &options);
  } catch (const DaemonConfigFileError&) {
    return 0;
  }
  try {
    JointMessageDecoder decoder(options.format, fuzz::Leg().dof_names);
  } catch (const std::invalid_argument&) {
  }
  return 0;
}
