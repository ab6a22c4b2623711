/// @file daemon_config_file.hpp
/// inertiald's --config file from disk: the file read, parsed as JSON and applied over a
/// DaemonOptions (ApplyDaemonConfig, daemon_config.hpp), with the three ways it can fail told apart
/// (cannot be read, not JSON, not a valid configuration) so that each program can phrase them.
#pragma once

#include <stdexcept>
#include <string>

#include "inertial/config/daemon_config.hpp"

namespace inertial {

/// A --config file that could not be used. what() is the detail alone: CannotText's "cannot read
/// the configuration '<path>': <reason>" for kUnreadable, TooLargeText's (input_file.hpp: more than
/// kMaxSettingsFileBytes, refused before parsing) for kTooLarge, the JSON parser's message for
/// kNotJson, ApplyDaemonConfig's message (naming the key) for kInvalid.
class DaemonConfigFileError : public std::runtime_error {
 public:
  enum class Reason { kUnreadable, kTooLarge, kNotJson, kInvalid };
  DaemonConfigFileError(Reason reason, const std::string& detail) : std::runtime_error(detail), reason_(reason) {}
  Reason reason() const { return reason_; }

 private:
  Reason reason_;
};

/// Reads the JSON configuration at `path` and applies it over *options (absent keys keep their
/// values). On failure *options may be partly changed. @throws DaemonConfigFileError.
void ApplyDaemonConfigFile(const std::string& path, DaemonOptions* options);
/// The same for the file's text; `source` names it in messages.
void ApplyDaemonConfigText(const std::string& text, const std::string& source, DaemonOptions* options);

}  // namespace inertial
