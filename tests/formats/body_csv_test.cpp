// The single-body CSV: time stamps checked as the joint CSV's (refused or scaled), and a log
// written and read back exactly.
#include "inertial/formats/body_csv.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <sstream>
#include <stdexcept>

#include "formats/time_stamps.hpp"

namespace inertial {
namespace {

using testing::Stamps;

// The single-body CSV checks its time stamps the same way.
TEST(BodyCsv, TimeStampsThatAreNotSecondsAreRefusedOrScaled) {
  auto body = [](const std::vector<std::string>& stamps) {
    std::string text = "wx,wy,wz,vx,vy,vz,mx,my,mz,fx,fy,fz,t\n";
    for (const std::string& t : stamps) text += "0.1,0.2,0.3,0,0,0,0,0,0,0,0,-9.81," + t + "\n";
    return text;
  };
  {
    std::istringstream in(body(Stamps(1700000000000.0, 10.0, 4, "%.0f")));
    try {
      ParseBodyCsv(in, "body.csv");
      ADD_FAILURE() << "no error";
    } catch (const CsvError& e) {
      EXPECT_EQ(std::string(e.what()),
                "body.csv: column 13 't': the time stamps do not look like seconds: median step 10 (as seconds, slower "
                "than 1 Hz), every stamp an integer; if they are milliseconds, give --time-scale 1e-3 (a median step of "
                "0.01 s)");
    }
  }
  std::istringstream in(body(Stamps(1700000000000.0, 10.0, 4, "%.0f")));
  const BodyLog log = ParseBodyCsv(in, "body.csv", nullptr, 1e-3);
  ASSERT_EQ(log.samples.size(), 4u);
  EXPECT_NEAR(log.samples[3].t - log.samples[0].t, 0.03, 5e-7);  // doubles near 1.7e9 s: 2.4e-7 s apart
  std::istringstream seconds(body(Stamps(0.0, 0.1, 4)));
  EXPECT_EQ(ParseBodyCsv(seconds, "body.csv").samples[1].t, 0.1);
  std::istringstream negative(body(Stamps(0.0, 0.1, 4)));
  EXPECT_THROW(ParseBodyCsv(negative, "body.csv", nullptr, -1e-3), std::invalid_argument);
}

// Columns in any order, gravity optional; what is written is read back bit for bit (%.17g).
TEST(BodyCsv, ReadsTheColumnsAndWritesThemBackExactly) {
  std::istringstream in(
      "fz,t,wx,wy,wz,vx,vy,vz,mx,my,mz,fx,fy,gx,gy,gz,note\n"
      "-9.81,0.0,0.1,0.2,0.3,0.4,0.5,0.6,1,2,3,4,5,0,0,-9.81,a\n"
      "-9.5,0.01,0.11,0.21,0.31,0.41,0.51,0.61,1.1,2.1,3.1,4.1,5.1,0,0.1,-9.8,b\n");
  std::vector<std::string> notices;
  const BodyLog log = ParseBodyCsv(in, "body.csv", &notices);
  ASSERT_EQ(log.samples.size(), 2u);
  EXPECT_EQ(notices.size(), 1u);  // the ignored column
  EXPECT_EQ(log.samples[1].t, 0.01);
  EXPECT_EQ(log.samples[1].twist[5], 0.61);
  EXPECT_EQ(log.samples[1].wrench[0], 1.1);
  EXPECT_EQ(log.samples[1].wrench[5], -9.5);
  ASSERT_EQ(log.gravity.size(), 2u);
  EXPECT_EQ(log.gravity[1], Vector3(0, 0.1, -9.8));
  const std::string path = ::testing::TempDir() + "inertial_body_csv_roundtrip.csv";
  WriteBodyCsv(path, log);
  const BodyLog back = ReadBodyCsv(path);
  std::filesystem::remove(path);
  ASSERT_EQ(back.samples.size(), 2u);
  ASSERT_EQ(back.gravity.size(), 2u);
  for (std::size_t k = 0; k < 2; ++k) {
    EXPECT_EQ(back.samples[k].t, log.samples[k].t);
    EXPECT_EQ(back.samples[k].twist, log.samples[k].twist);
    EXPECT_EQ(back.samples[k].wrench, log.samples[k].wrench);
    EXPECT_EQ(back.gravity[k], log.gravity[k]);
  }
  std::istringstream missing("t,wx,wy,wz\n0,0,0,0\n0.1,0,0,0\n");
  EXPECT_THROW(ParseBodyCsv(missing, "body.csv"), CsvError);
}

}  // namespace
}  // namespace inertial
