/// @file input_file.hpp
/// Reading a whole input file with a size limit checked before a byte of it is parsed. Parsers of
/// settings files (yaml-cpp above all) can spend seconds and gigabytes on a hostile file of a
/// megabyte (one value of 1.5 million commas: 5.5 s and 1.4 GB in yaml-cpp, issue 35), so a file
/// far larger than any honest one of its kind is refused by its size, with a message that says the
/// limit. The text parsers (ParseUrdf, ParseCanConfig, ApplyDaemonConfigText) check the same limits
/// on text they are handed.
///
/// The limits, from what the files hold:
/// - settings files (inertiald's --config JSON, motors.yaml): a motor or a joint takes 100-300
///   bytes, so a 100-joint robot's file is 10-30 KiB; 64 KiB leaves twice that for comments. At the
///   limit yaml-cpp's worst case measured here is 0.25 s (commas in a flow mapping).
/// - URDFs: a link with its visual, collision and inertial elements takes 1-2 KiB, so a 1000-link
///   model is a few MiB; 16 MiB. tinyxml2 and urdfdom read a URDF in time linear in its size once its
///   nesting, attributes per tag and links are bounded (urdf_model.hpp), about 0.1 s per MiB.
/// - checkpoints (estimator_state_file.hpp): n parameters and their n x n covariance at up to 25
///   characters a number, so 1100 parameters (a 100-link robot with effects, four times the bundled
///   28-link chain, beyond real time for the dense estimator) is 30 MB; 32 MiB. nlohmann::json
///   parses them in linear time, but its tree takes up to 30 bytes for a byte of text (a file of
///   empty arrays): 32 MiB keeps that under a gigabyte.
#pragma once

#include <cstddef>
#include <stdexcept>
#include <string>

namespace inertial {

inline constexpr std::size_t kMaxSettingsFileBytes = std::size_t{64} * 1024;
inline constexpr std::size_t kMaxUrdfBytes = std::size_t{16} * 1024 * 1024;
inline constexpr std::size_t kMaxStateFileBytes = std::size_t{32} * 1024 * 1024;

/// A file that cannot be read (what() is CannotText's wording) or is larger than its kind's limit
/// (what() is TooLargeText's).
class InputFileError : public std::runtime_error {
 public:
  enum class Reason { kUnreadable, kTooLarge };
  InputFileError(Reason reason, const std::string& message) : std::runtime_error(message), reason_(reason) {}
  Reason reason() const { return reason_; }

 private:
  Reason reason_;
};

/// "<source>: the <what> is <size> bytes, over its limit of <limit in bytes, KiB or MiB>: refused
/// before parsing". `size` may be a lower bound ("at least").
std::string TooLargeText(const std::string& source, const std::string& what, std::size_t size, std::size_t limit,
                         bool at_least = false);

/// The whole file at `path` as bytes, at most `max_bytes` of them. Reads no more than max_bytes + 1
/// bytes whatever the file is (a device, a file that grows while it is read). @throws
/// InputFileError naming the file and `what` (e.g. "URDF").
std::string ReadInputFile(const std::string& path, const std::string& what, std::size_t max_bytes);

}  // namespace inertial
