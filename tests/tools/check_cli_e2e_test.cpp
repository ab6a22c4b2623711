// End-to-end tests of `inertial check [--repair]`: the built CLI on the bundled robots and on URDFs
// with impossible links, the repaired file checked again by the library.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "cli_support.hpp"
#include "inertial/inertia/consistency.hpp"
#include "inertial/formats/urdf_model.hpp"
#include "formats/urdf_text.hpp"
#include "simulated_robot.hpp"

namespace inertial {
namespace {

using testing::Contains;
using testing::Describe;
using testing::Example;
using testing::RunCli;

// A two-link arm whose second link violates a triangle inequality at the COM (Izz > Ixx + Iyy:
// a body thinner than a plate), with its COM off the link origin in a rotated COM frame.
std::string ImpossibleArm() {
  using namespace testing;
  Matrix3 good = Vector3(0.02, 0.03, 0.025).asDiagonal();
  Matrix3 bad = Vector3(0.01, 0.012, 0.05).asDiagonal();
  return RobotXml("bad_arm", LinkXml("base") +
                                 LinkXml("upper", InertialXml(1.5, Vector3(0, 0, 0.1), Vector3::Zero(), good)) +
                                 LinkXml("fore", InertialXml(0.8, Vector3(0.1, 0.02, 0), Vector3(0.3, 0, 0.2), bad)) +
                                 JointXml("shoulder", "revolute", "base", "upper") +
                                 JointXml("elbow", "revolute", "upper", "fore", Vector3(0, 0, 0.3), Vector3::Zero(),
                                          Vector3::UnitY()));
}

TEST(CheckCli, BundledRobotsAreConsistent) {
  for (const char* file : {"leg3.urdf", "arm7.urdf"}) {
    const testing::CliRun r = RunCli({"check", "--model", Example(file)});
    EXPECT_EQ(r.exit_code, 0) << Describe(r);
    EXPECT_TRUE(Contains(r.out, "all physically consistent")) << r.out;
  }
}

TEST(CheckCli, ImpossibleLinkIsNamedWithItsFailedCheckAndRepaired) {
  const auto in = testing::TempUrdfPath("bad.urdf"), out = testing::TempUrdfPath("fixed.urdf");
  testing::WriteTextFile(in, ImpossibleArm());
  const testing::CliRun r = RunCli({"check", "--model", in.string(), "--json"});
  ASSERT_EQ(r.exit_code, 4) << Describe(r);
  const nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["impossible"], 1);
  for (const auto& link : j["links"]) {
    if (link["link"] == "fore") {
      EXPECT_FALSE(link["physically_consistent"].get<bool>());
      EXPECT_TRUE(Contains(link["reason"].get<std::string>(), "triangle")) << link.dump();
      // Dx + Dy - Dz = 0.01 + 0.012 - 0.05 at the COM, whatever the COM frame's rotation.
      EXPECT_NEAR(link["min_triangle_margin"].get<double>(), -0.028, 1e-12);
    } else if (link["link"] == "upper") {
      EXPECT_TRUE(link["physically_consistent"].get<bool>());
    }
  }
  const testing::CliRun text = RunCli({"check", "--model", in.string()});
  EXPECT_EQ(text.exit_code, 4);
  EXPECT_TRUE(Contains(text.out, "fore: IMPOSSIBLE")) << text.out;

  const testing::CliRun repair = RunCli({"check", "--model", in.string(), "--repair", out.string()});
  EXPECT_EQ(repair.exit_code, 4) << Describe(repair);  // the file checked is still impossible
  EXPECT_TRUE(Contains(repair.out, "every inertial in it is physically consistent")) << repair.out;
  EXPECT_EQ(RunCli({"check", "--model", out.string()}).exit_code, 0);
  // The repair keeps mass and COM, and leaves the consistent link alone.
  const RobotModel before = LoadUrdf(in.string(), UrdfLoadOptions{false});
  const RobotModel after = LoadUrdf(out.string());
  for (size_t k = 0; k < before.links.size(); ++k) {
    if (!before.links[k].present) continue;
    const InertialParams& a = before.links[k].pi;
    const InertialParams& b = after.links[k].pi;
    EXPECT_NEAR(a.mass(), b.mass(), 1e-15);
    EXPECT_LT((a.com() - b.com()).norm(), 1e-15);
    EXPECT_TRUE(IsPhysicallyConsistent(b)) << after.links[k].link;
    if (before.links[k].link == "upper") {
      EXPECT_LT((a.vector() - b.vector()).norm(), 1e-15);
    }
  }
}

TEST(CheckCli, RefusesToRepairOverTheFileItChecks) {
  const auto in = testing::TempUrdfPath("bad_in_place.urdf");
  testing::WriteTextFile(in, ImpossibleArm());
  const std::string before = testing::ReadTextFile(in);
  // The same file, once by its name and once through another spelling of its directory.
  const std::string other = (in.parent_path() / "." / in.filename()).string();
  for (const std::string& repair : {in.string(), other}) {
    const testing::CliRun r = RunCli({"check", "--model", in.string(), "--repair", repair});
    EXPECT_EQ(r.exit_code, 2) << Describe(r);
    EXPECT_TRUE(Contains(r.err, "--repair '" + repair + "' is the --model input: refusing to overwrite an input"))
        << r.err;
  }
  EXPECT_EQ(testing::ReadTextFile(in), before);  // untouched
}

TEST(CheckCli, FilesThatAreNotUrdfAreIoErrorsNamingThePath) {
  const auto path = testing::TempUrdfPath("not.urdf");
  testing::WriteTextFile(path, "<html><body>hello</body></html>");
  const testing::CliRun r = RunCli({"check", "--model", path.string()});
  EXPECT_EQ(r.exit_code, 5) << Describe(r);
  EXPECT_TRUE(Contains(r.err, path.string())) << r.err;
  EXPECT_EQ(RunCli({"check", "--model", "/nonexistent/robot.urdf"}).exit_code, 5);
}

}  // namespace
}  // namespace inertial
