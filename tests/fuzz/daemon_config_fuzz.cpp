// Fuzz harness: inertiald's --config JSON (estimation_daemon.hpp) as main() reads it: parsed, then
// applied to the options; an accepted message format must then build the leg's decoder or be
// refused by name, as the daemon's start does.
#include "fuzz_support.hpp"
#include "inertial/runtime/estimation_daemon.hpp"
#include "inertial/transport/joint_message.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace inertial;
  nlohmann::json config;
  try {
    config = nlohmann::json::parse(fuzz::Text(data, size));
  } catch (const nlohmann::json::exception&) {
    return 0;
  }
  DaemonOptions options;
  try {
    ApplyDaemonConfig(config, &options);
  } catch (const std::invalid_argument&) {
    return 0;
  }
  try {
    JointMessageDecoder decoder(options.format, fuzz::Leg().dof_names);
  } catch (const std::invalid_argument&) {
  }
  return 0;
}
