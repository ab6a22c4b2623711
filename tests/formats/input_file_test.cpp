// Input files read whole with a size limit checked before parsing (issue 35): the limit refused with
// its wording, the file at the limit read byte for byte, files that cannot be read named.
#include "inertial/formats/input_file.hpp"

#include <gtest/gtest.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

#include "cli_support.hpp"

namespace inertial {
namespace {

std::string ErrorOf(const std::string& path, std::size_t limit, InputFileError::Reason* reason = nullptr) {
  try {
    ReadInputFile(path, "thing", limit);
  } catch (const InputFileError& e) {
    if (reason != nullptr) *reason = e.reason();
    return e.what();
  }
  ADD_FAILURE() << path << " was read";
  return "";
}

TEST(InputFile, ReadsAFileUpToTheLimitByteForByte) {
  std::string bytes;
  for (int k = 0; k < 200000; ++k) bytes += static_cast<char>(k * 7919 % 256);  // every byte value, NULs included
  const std::string path = testing::WriteUniqueTempFile("bytes", "");
  std::ofstream(path, std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  EXPECT_EQ(ReadInputFile(path, "thing", bytes.size()), bytes);
  EXPECT_EQ(ReadInputFile(path, "thing", 10 * bytes.size()), bytes);
  InputFileError::Reason reason{};
  EXPECT_EQ(ErrorOf(path, bytes.size() - 1, &reason),
            path + ": the thing is 200000 bytes, over its limit of 199999 bytes: refused before parsing");
  EXPECT_EQ(reason, InputFileError::Reason::kTooLarge);
  EXPECT_EQ(ReadInputFile(testing::WriteUniqueTempFile("empty", ""), "thing", 0), "");
  std::filesystem::remove(path);
}

TEST(InputFile, LimitsAreWrittenInTheirBinaryUnit) {
  EXPECT_EQ(TooLargeText("a", "URDF", 16777217, kMaxUrdfBytes),
            "a: the URDF is 16777217 bytes, over its limit of 16 MiB: refused before parsing");
  EXPECT_EQ(TooLargeText("b", "configuration", 70000, kMaxSettingsFileBytes, true),
            "b: the configuration is at least 70000 bytes, over its limit of 64 KiB: refused before "
            "parsing");
}

// A device that never ends is read no further than the limit (its size is not known beforehand).
TEST(InputFile, AnEndlessDeviceIsReadOnlyToTheLimit) {
  if (!std::filesystem::exists("/dev/zero")) GTEST_SKIP() << "no /dev/zero";
  EXPECT_EQ(ErrorOf("/dev/zero", kMaxSettingsFileBytes),
            "/dev/zero: the thing is at least 65537 bytes, over its limit of 64 KiB: refused before parsing");
}

TEST(InputFile, FilesThatCannotBeReadAreNamedWithTheSystemsReason) {
  InputFileError::Reason reason{};
  EXPECT_EQ(ErrorOf("/nonexistent-dir-of-inertial/x", 10, &reason),
            std::string("cannot read the thing '/nonexistent-dir-of-inertial/x': ") + std::strerror(ENOENT));
  EXPECT_EQ(reason, InputFileError::Reason::kUnreadable);
  const std::string dir = std::filesystem::temp_directory_path().string();
  EXPECT_EQ(ErrorOf(dir, 10), "cannot read the thing '" + dir + "': " + std::strerror(EISDIR));
}

}  // namespace
}  // namespace inertial
