// inertiald's --config file read from disk: its keys reach the options (absent ones keep theirs),
// and the three ways a file can fail are told apart, each with its own message.
#include "inertial/config/daemon_config_file.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "cli_support.hpp"
#include "inertial/formats/input_file.hpp"

namespace inertial {
namespace {

DaemonConfigFileError ErrorOf(const std::string& path) {
  DaemonOptions options;
  try {
    ApplyDaemonConfigFile(path, &options);
  } catch (const DaemonConfigFileError& e) {
    return e;
  }
  ADD_FAILURE() << path << " was accepted";
  return DaemonConfigFileError(DaemonConfigFileError::Reason::kInvalid, "");
}

TEST(DaemonConfigFile, TheFilesKeysReachTheOptionsAndAbsentKeysKeepTheirValues) {
  const std::string path = testing::WriteUniqueTempFile("config.json", R"({"channel": "ARM_STATE", "publish_rate_hz": 25, "noise_tau": 0.4})");
  DaemonOptions options;
  options.checkpoint_path = "before.json";
  ApplyDaemonConfigFile(path, &options);
  EXPECT_EQ(options.input_channel, "ARM_STATE");
  EXPECT_EQ(options.publish_rate_hz, 25.0);
  EXPECT_EQ(options.estimator.measurement_sigma, 0.4);
  EXPECT_EQ(options.checkpoint_path, "before.json");
  EXPECT_EQ(options.estimate_channel, "INERTIAL_ESTIMATE");
  std::filesystem::remove(path);
}

TEST(DaemonConfigFile, AMissingFileCannotBeRead) {
  const std::string path = testing::UniqueTempPath("absent.json").string();
  const DaemonConfigFileError e = ErrorOf(path);
  EXPECT_EQ(e.reason(), DaemonConfigFileError::Reason::kUnreadable);
  EXPECT_EQ(std::string(e.what()), "cannot read the configuration '" + path + "': No such file or directory");
}

// Issue 35: settings files are small; one over kMaxSettingsFileBytes is refused by its size before
// any parser sees it, at once.
TEST(DaemonConfigFile, AFileOverTheSettingsLimitIsRefusedBeforeParsing) {
  std::string text = R"({"channel": ")" + std::string(kMaxSettingsFileBytes, 'x') + "\"}";
  const std::string path = testing::WriteUniqueTempFile("big.json", text);
  DaemonConfigFileError e = ErrorOf(path);
  EXPECT_EQ(e.reason(), DaemonConfigFileError::Reason::kTooLarge);
  EXPECT_EQ(std::string(e.what()), path + ": the configuration is " + std::to_string(text.size()) + " bytes, over its limit of 64 KiB: refused before parsing");
  DaemonOptions options;
  EXPECT_THROW(ApplyDaemonConfigText(text, "text.json", &options), DaemonConfigFileError);
  EXPECT_EQ(options.input_channel, DaemonOptions().input_channel);
  // At the limit it is read.
  text = R"({"channel": ")" + std::string(kMaxSettingsFileBytes - 15, 'x') + "\"}";
  ASSERT_EQ(text.size(), kMaxSettingsFileBytes);
  ApplyDaemonConfigText(text, "text.json", &options);
  EXPECT_EQ(options.input_channel.size(), kMaxSettingsFileBytes - 15);
  std::filesystem::remove(path);
}

TEST(DaemonConfigFile, TextThatIsNotJsonIsToldApartFromAnInvalidConfiguration) {
  const std::string not_json = testing::WriteUniqueTempFile("config.json", "{\"channel\": ");
  const DaemonConfigFileError parse = ErrorOf(not_json);
  EXPECT_EQ(parse.reason(), DaemonConfigFileError::Reason::kNotJson);
  EXPECT_EQ(std::string(parse.what()).rfind("[json.exception.parse_error.", 0), 0u) << parse.what();

  const std::string invalid = testing::WriteUniqueTempFile("config.json", R"({"chanel": "ARM_STATE"})");
  const DaemonConfigFileError key = ErrorOf(invalid);
  EXPECT_EQ(key.reason(), DaemonConfigFileError::Reason::kInvalid);
  EXPECT_EQ(std::string(key.what()), "config: unknown key \"chanel\"");

  const std::string not_object = testing::WriteUniqueTempFile("config.json", "[1, 2]");
  EXPECT_EQ(ErrorOf(not_object).reason(), DaemonConfigFileError::Reason::kInvalid);
  EXPECT_EQ(std::string(ErrorOf(not_object).what()), "config: expected a JSON object");
  for (const std::string& p : {not_json, invalid, not_object}) std::filesystem::remove(p);
}

}  // namespace
}  // namespace inertial
