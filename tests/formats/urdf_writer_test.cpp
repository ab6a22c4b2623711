#include "inertial/formats/urdf_writer.hpp"

#include <gtest/gtest.h>
#include <urdf_parser/urdf_parser.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <limits>
#include <string>

#include "inertial/inertia/closed_form_bodies.hpp"
#include "formats/urdf_text.hpp"
#include "test_support.hpp"

namespace inertial {
namespace {

namespace fs = std::filesystem;
using testing::InertialXml;
using testing::JointXml;
using testing::LinkXml;
using testing::RelativeError;
using testing::Rng;
using testing::RobotXml;

using testing::ErrorOf;

std::size_t Count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

const UrdfLinkInertial& LinkInertial(const RobotModel& model, const std::string& link) {
  for (const UrdfLinkInertial& li : model.links) {
    if (li.link == link) return li;
  }
  throw std::runtime_error("test: no link " + link);
}

// Removes its files when the test ends.
struct TempFiles {
  fs::path in = testing::TempUrdfPath("in.urdf"), out = testing::TempUrdfPath("out.urdf");
  ~TempFiles() {
    std::error_code ec;
    fs::remove(in, ec);
    fs::remove(out, ec);
  }
};

// base -> j1 (revolute) -> l1 (+ tip fixed to it, with mass) -> j2 (prismatic) -> l2 -> j3 -> l3,
// with a visual, a comment and a non-URDF element that must survive.
std::string Robot() {
  const Matrix3 I = Vector3(0.02, 0.03, 0.04).asDiagonal();
  return RobotXml(
      "writer",
      "<!-- keep this comment -->\n<gazebo reference=\"l1\"><mu1>0.7</mu1></gazebo>\n" + LinkXml("base") +
          LinkXml("l1", InertialXml(2.0, Vector3(0.1, 0.02, -0.03), Vector3(0.3, -0.2, 1.1), I) +
                            "<visual><geometry><mesh filename=\"package://writer/l1.stl\"/></geometry></visual>") +
          JointXml("j1", "revolute", "base", "l1", Vector3(0, 0, 0.2), Vector3(0.1, 0.2, 0.3), Vector3(0, 1, 1)) +
          JointXml("tip_fixed", "fixed", "l1", "tip", Vector3(0.3, 0, 0), Vector3(0, 0.4, 0)) +
          LinkXml("tip", InertialXml(0.4, Vector3(0.02, 0, 0), Vector3(0.5, 0, 0), 0.1 * I)) +
          JointXml("j2", "prismatic", "tip", "l2", Vector3(0.05, 0, 0), Vector3(0, 0, 0.7), Vector3::UnitX()) +
          LinkXml("l2", InertialXml(1.0, Vector3(0, 0.05, 0), Vector3::Zero(), 0.5 * I)) +
          JointXml("j3", "continuous", "l2", "l3", Vector3(0, 0.1, 0), Vector3(0.2, 0, 0), Vector3::UnitY(),
                   "<dynamics damping=\"9\" friction=\"9\"/>") +
          LinkXml("l3", InertialXml(0.7, Vector3(0.1, 0, 0), Vector3(0, 0, 0.3), 0.3 * I)));
}

TEST(UrdfWriter, RoundTripWithAFixedLinkMergedIntoItsParent) {
  TempFiles files;
  testing::WriteTextFile(files.in, Robot());
  const RobotModel before = LoadUrdf(files.in.string());
  // l1's new inertia is its body's (l1 and tip merged); tip's own <inertial> goes.
  WriteUrdfWithInertias(files.in.string(), files.out.string(), {{"l1", before.tree.inertia(0)}}, {"tip"},
                        {{"j1", {0.5, 0.125}}, {"j3", {0.25, 1.5}}});
  const RobotModel after = LoadUrdf(files.out.string());

  ASSERT_EQ(after.dof_names, before.dof_names);
  EXPECT_FALSE(LinkInertial(after, "tip").present);
  EXPECT_LT(RelativeError(LinkInertial(after, "l1").pi.vector(), before.tree.inertia(0).vector()), 1e-15);
  // Untouched links read back bit for bit.
  for (const std::string link : {"l2", "l3"}) {
    EXPECT_EQ(LinkInertial(after, link).pi.vector(), LinkInertial(before, link).pi.vector()) << link;
  }
  Rng rng(23);
  for (int k = 0; k < 20; ++k) {
    const Eigen::VectorXd q = rng.UniformVector<3>(-2, 2), qd = rng.UniformVector<3>(-2, 2),
                          qdd = rng.UniformVector<3>(-5, 5);
    EXPECT_LT(RelativeError(after.tree.InverseDynamics(q, qd, qdd), before.tree.InverseDynamics(q, qd, qdd)), 1e-12);
  }

  const std::string text = testing::ReadTextFile(files.out);
  const urdf::ModelInterfaceSharedPtr parsed = urdf::parseURDF(text);
  ASSERT_TRUE(parsed);
  ASSERT_TRUE(parsed->getJoint("j1")->dynamics);
  EXPECT_EQ(parsed->getJoint("j1")->dynamics->damping, 0.5);
  EXPECT_EQ(parsed->getJoint("j1")->dynamics->friction, 0.125);
  EXPECT_EQ(parsed->getJoint("j3")->dynamics->damping, 0.25);
  EXPECT_EQ(parsed->getJoint("j3")->dynamics->friction, 1.5);
  EXPECT_FALSE(parsed->getJoint("j2")->dynamics);
  EXPECT_EQ(Count(text, "<dynamics damping="), 2u);
  EXPECT_NE(text.find("package://writer/l1.stl"), std::string::npos);
  EXPECT_NE(text.find("<gazebo reference=\"l1\">"), std::string::npos);
  EXPECT_NE(text.find("keep this comment"), std::string::npos);
  EXPECT_NE(text.find("Written by inertial from " + files.in.string() +
                      ": new <inertial> for links l1; <inertial> removed from links tip; <dynamics> set for joints "
                      "j1, j3."),
            std::string::npos);

  // Rewriting a written file keeps one note.
  WriteUrdfWithInertias(files.out.string(), files.out.string(), {}, {}, {});
  EXPECT_EQ(Count(testing::ReadTextFile(files.out), "Written by inertial"), 1u);
}

TEST(UrdfWriter, WrittenInertiasReadBackAsGiven) {
  TempFiles files;
  testing::WriteTextFile(files.in, Robot());
  Rng rng(29);
  const InertialParams l2 = SolidBox(1.3, 0.1, 0.2, 0.3, rng.RandomPose<Pose>(0.2));
  const InertialParams l3 = SolidCylinder(0.6, 0.03, 0.25, rng.RandomPose<Pose>(0.2));
  const InertialParams tip = SolidSphere(0.2, 0.04, rng.RandomPose<Pose>(0.1));
  WriteUrdfWithInertias(files.in.string(), files.out.string(), {{"l2", l2}, {"l3", l3}, {"tip", tip}}, {}, {});
  const RobotModel after = LoadUrdf(files.out.string());
  EXPECT_LT(RelativeError(LinkInertial(after, "l2").pi.vector(), l2.vector()), 1e-15);
  EXPECT_LT(RelativeError(LinkInertial(after, "l3").pi.vector(), l3.vector()), 1e-15);
  EXPECT_LT(RelativeError(LinkInertial(after, "tip").pi.vector(), tip.vector()), 1e-15);
  EXPECT_EQ(Count(testing::ReadTextFile(files.out), "<mass value="), 4u);  // l1's untouched, three new
}

TEST(UrdfWriter, InertialAddedToALinkWithoutOne) {
  TempFiles files;
  testing::WriteTextFile(files.in, RobotXml("r", LinkXml("a") + LinkXml("b") + JointXml("j", "continuous", "a", "b")));
  const InertialParams body = SolidBox(1.0, 0.1, 0.2, 0.3, Pose{Matrix3::Identity(), Vector3(0, 0, 0.1)});
  WriteUrdfWithInertias(files.in.string(), files.out.string(), {{"b", body}}, {"a"}, {});
  const RobotModel model = LoadUrdf(files.out.string());
  EXPECT_LT(RelativeError(model.tree.inertia(0).vector(), body.vector()), 1e-15);
}

TEST(UrdfWriter, ExampleLegRoundTrip) {
  const char* dir = std::getenv("INERTIAL_SOURCE_DIR");
  if (dir == nullptr) GTEST_SKIP() << "INERTIAL_SOURCE_DIR is not set (run through ctest)";
  TempFiles files;
  const std::string in = std::string(dir) + "/examples/leg3.urdf";
  const RobotModel before = LoadUrdf(in);
  std::map<std::string, InertialParams> bodies;
  for (int i = 0; i < before.tree.num_bodies(); ++i) bodies[before.body_links[i]] = before.tree.inertia(i);
  WriteUrdfWithInertias(in, files.out.string(), bodies, {"foot"}, {{"knee", {0.1, 0.2}}});
  const RobotModel after = LoadUrdf(files.out.string());
  Rng rng(31);
  for (int k = 0; k < 20; ++k) {
    const Eigen::VectorXd q = rng.UniformVector<3>(-2, 2), qd = rng.UniformVector<3>(-2, 2),
                          qdd = rng.UniformVector<3>(-5, 5);
    EXPECT_LT(RelativeError(after.tree.InverseDynamics(q, qd, qdd), before.tree.InverseDynamics(q, qd, qdd)), 1e-12);
  }
}

TEST(UrdfWriterErrors, UnknownNamesAreListed) {
  TempFiles files;
  testing::WriteTextFile(files.in, Robot());
  const std::string in = files.in.string(), out = files.out.string();
  EXPECT_EQ(ErrorOf([&] { WriteUrdfWithInertias(in, out, {{"l9", InertialParams()}, {"l8", InertialParams()}}, {}, {}); }),
            in + ": no link named 'l8', 'l9'");
  EXPECT_EQ(ErrorOf([&] { WriteUrdfWithInertias(in, out, {}, {"nope"}, {}); }), in + ": no link named 'nope'");
  EXPECT_EQ(ErrorOf([&] { WriteUrdfWithInertias(in, out, {}, {}, {{"elbow", {}}}); }), in + ": no joint named 'elbow'");
  EXPECT_FALSE(fs::exists(files.out));
}

TEST(UrdfWriterErrors, ContradictoryOrNonFiniteInput) {
  TempFiles files;
  testing::WriteTextFile(files.in, Robot());
  const std::string in = files.in.string(), out = files.out.string();
  EXPECT_EQ(ErrorOf([&] { WriteUrdfWithInertias(in, out, {{"tip", InertialParams()}}, {"tip"}, {}); }),
            in + ": link 'tip' is both given a new <inertial> and listed for removal");
  Vector10 nan_pi = Vector10::Ones();
  nan_pi[3] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(ErrorOf([&] { WriteUrdfWithInertias(in, out, {{"l2", InertialParams::FromVector(nan_pi)}}, {}, {}); }),
            in + ": link 'l2': the new inertia is not finite");
  EXPECT_EQ(ErrorOf([&] { WriteUrdfWithInertias(in, out, {}, {}, {{"j1", {std::nan(""), 0}}}); }),
            in + ": joint 'j1': damping or friction is not finite");
}

TEST(UrdfWriterErrors, UnreadableInputAndUnwritableOutput) {
  TempFiles files;
  const std::string missing = "/nonexistent_dir_for_inertial/in.urdf";
  EXPECT_EQ(ErrorOf([&] { WriteUrdfWithInertias(missing, files.out.string(), {}, {}, {}); })
                .rfind("cannot read the URDF '" + missing + "': No such file or directory", 0),
            0u);
  testing::WriteTextFile(files.in, "<robot name='r'><link name='a'></robot>");
  EXPECT_EQ(ErrorOf([&] { WriteUrdfWithInertias(files.in.string(), files.out.string(), {}, {}, {}); })
                .rfind(files.in.string() + ": is not a valid URDF: XML error at line 1", 0),
            0u);
  testing::WriteTextFile(files.in, Robot());
  const std::string unwritable = "/nonexistent_dir_for_inertial/out.urdf";
  EXPECT_EQ(ErrorOf([&] { WriteUrdfWithInertias(files.in.string(), unwritable, {}, {}, {}); })
                .rfind("cannot write '" + unwritable + "': No such file or directory", 0),
            0u);
}

}  // namespace
}  // namespace inertial
