// OutputPathClash and SameFile: an output naming an input (by its own spelling, another spelling
// or a symbolic link) or another output is refused with the one wording every program prints.
#include "inertial/formats/output_paths.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <unistd.h>

namespace inertial {
namespace {

namespace fs = std::filesystem;

class OutputPaths : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("inertial_output_paths_" + std::to_string(::getpid()));
    fs::create_directories(dir_ / "sub");
    data_ = (dir_ / "data.csv").string();
    std::ofstream(data_) << "t\n0\n";
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
  std::string data_;
};

TEST_F(OutputPaths, SameFileSeesThroughSpellingsAndLinks) {
  EXPECT_TRUE(SameFile(data_, data_));
  EXPECT_TRUE(SameFile(data_, (dir_ / "sub" / ".." / "data.csv").string()));
  const fs::path link = dir_ / "link.csv";
  fs::create_symlink(data_, link);
  EXPECT_TRUE(SameFile(link.string(), data_));
  // A file not yet written is compared by its path.
  EXPECT_TRUE(SameFile((dir_ / "new.csv").string(), (dir_ / "sub" / ".." / "new.csv").string()));
  EXPECT_FALSE(SameFile((dir_ / "new.csv").string(), data_));
  EXPECT_FALSE(SameFile("", data_));  // not given
  EXPECT_FALSE(SameFile("", ""));
}

TEST_F(OutputPaths, NamesTheFirstOutputThatIsAnInput) {
  const std::string respelled = (dir_ / "." / "data.csv").string();
  const std::optional<std::string> clash =
      OutputPathClash({{"--out", (dir_ / "fit.csv").string()}, {"--predictions", respelled}},
                      {{"--model", (dir_ / "leg.urdf").string()}, {"--data", data_}});
  ASSERT_TRUE(clash.has_value());
  EXPECT_EQ(*clash, "--predictions '" + respelled +
                        "' is the --data input: refusing to overwrite an input (choose another output path)");
}

TEST_F(OutputPaths, NamesTwoOutputsOfOneFile) {
  const std::string out = (dir_ / "out.csv").string();
  const std::optional<std::string> clash =
      OutputPathClash({{"--out", out}, {"--write-log", (dir_ / "sub" / ".." / "out.csv").string()}}, {{"--data", data_}});
  ASSERT_TRUE(clash.has_value());
  EXPECT_EQ(*clash, "--out and --write-log name the same file '" + out + "'");
}

TEST_F(OutputPaths, DistinctOrMissingPathsPass) {
  EXPECT_FALSE(OutputPathClash({{"--out", (dir_ / "a.csv").string()}, {"--write-urdf", ""}, {"--report", ""}},
                               {{"--data", data_}, {"--validate", ""}})
                   .has_value());
  EXPECT_FALSE(OutputPathClash({}, {{"--data", data_}}).has_value());
}

}  // namespace
}  // namespace inertial
