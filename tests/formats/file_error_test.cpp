#include "inertial/formats/file_error.hpp"

#include <gtest/gtest.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

namespace inertial {
namespace {

TEST(FileError, NamesTheFileWhatItIsAndTheSystemsReason) {
  EXPECT_EQ(CannotText("read", "LCM log", "/no/such.lcm", ENOENT),
            std::string("cannot read the LCM log '/no/such.lcm': ") + std::strerror(ENOENT));
  EXPECT_EQ(CannotText("write", "", "out.csv", EACCES), std::string("cannot write 'out.csv': ") + std::strerror(EACCES));
  EXPECT_EQ(CannotText("read", "", "x", 0), "cannot read 'x': unknown reason");
}

TEST(FileError, TakesErrnoOfTheFailureByDefault) {
  errno = 0;
  std::FILE* f = std::fopen("/nonexistent-dir-of-inertial/file", "r");
  ASSERT_EQ(f, nullptr);
  EXPECT_EQ(CannotText("read", "", "/nonexistent-dir-of-inertial/file"),
            std::string("cannot read '/nonexistent-dir-of-inertial/file': ") + std::strerror(ENOENT));
}

}  // namespace
}  // namespace inertial
