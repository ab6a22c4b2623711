#include "inertial/config/daemon_config_file.hpp"

#include <fstream>

#include "inertial/formats/file_error.hpp"

namespace inertial {

void ApplyDaemonConfigFile(const std::string& path, DaemonOptions* options) {
  std::ifstream in(path);
  if (!in) {
    throw DaemonConfigFileError(DaemonConfigFileError::Reason::kUnreadable,
                                CannotText("read", "configuration", path));
  }
  nlohmann::json config;
  try {
    config = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw DaemonConfigFileError(DaemonConfigFileError::Reason::kNotJson, e.what());
  }
  try {
    ApplyDaemonConfig(config, options);
  } catch (const std::exception& e) {
    throw DaemonConfigFileError(DaemonConfigFileError::Reason::kInvalid, e.what());
  }
}

}  // namespace inertial
