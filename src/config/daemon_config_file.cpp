#include "inertial/config/daemon_config_file.hpp"

#include "inertial/formats/input_file.hpp"

namespace inertial {

void ApplyDaemonConfigText(const std::string& text, const std::string& source, DaemonOptions* options) {
  if (text.size() > kMaxSettingsFileBytes) {
    throw DaemonConfigFileError(DaemonConfigFileError::Reason::kTooLarge,
                                TooLargeText(source, "configuration", text.size(), kMaxSettingsFileBytes));
  }
  nlohmann::json config;
  try {
    config = nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    throw DaemonConfigFileError(DaemonConfigFileError::Reason::kNotJson, e.what());
  }
  try {
    ApplyDaemonConfig(config, options);
  } catch (const std::exception& e) {
    throw DaemonConfigFileError(DaemonConfigFileError::Reason::kInvalid, e.what());
  }
}

void ApplyDaemonConfigFile(const std::string& path, DaemonOptions* options) {
  std::string text;
  try {
    text = ReadInputFile(path, "configuration", kMaxSettingsFileBytes);
  } catch (const InputFileError& e) {
    throw DaemonConfigFileError(e.reason() == InputFileError::Reason::kTooLarge
                                    ? DaemonConfigFileError::Reason::kTooLarge
                                    : DaemonConfigFileError::Reason::kUnreadable,
                                e.what());
  }
  ApplyDaemonConfigText(text, path, options);
}

}  // namespace inertial
