// Running gnuplot: a script's output lands in the given directory (a name with spaces and quotes:
// no shell), a failing script's error names it and the directory, and quoted strings double their
// quotes.
#include "inertial/report/gnuplot.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

#include "cli_support.hpp"

namespace inertial {
namespace {

namespace fs = std::filesystem;

TEST(Gnuplot, QuotedStringsDoubleTheirQuotes) {
  EXPECT_EQ(GnuplotQuoted("knee"), "'knee'");
  EXPECT_EQ(GnuplotQuoted("it's"), "'it''s'");
  EXPECT_EQ(GnuplotQuoted("a\nb"), "'ab'");  // a newline would end the literal
  EXPECT_EQ(GnuplotQuoted(""), "''");
}

TEST(Gnuplot, RunsInTheDirectoryAndNamesFailures) {
  const fs::path dir = testing::UniqueTempPath("gnuplot dir's");
  fs::create_directories(dir);
  {
    std::ofstream script(dir / "ok.gp");
    script << "set print " << GnuplotQuoted("out.txt") << "\nprint 6*7\n";
  }
  RunGnuplot(dir, "ok.gp");
  EXPECT_EQ(testing::ReadFile(dir / "out.txt"), "42\n");
  {
    std::ofstream script(dir / "bad.gp");
    script << "this is not gnuplot\n";
  }
  try {
    RunGnuplot(dir, "bad.gp");
    ADD_FAILURE() << "no error";
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("bad.gp"), std::string::npos) << what;
    EXPECT_NE(what.find(dir.string()), std::string::npos) << what;
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace inertial
