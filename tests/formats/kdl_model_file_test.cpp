// A model file (model_file.hpp) is still a URDF for other readers: ROS's kdl_parser (through
// urdfdom) builds a KDL tree from it with the written link inertias, ignoring <inertial_effects>.
#include <gtest/gtest.h>
#include <kdl/tree.hpp>
#include <kdl_parser/kdl_parser.hpp>

#include <filesystem>

#include "inertial/formats/model_file.hpp"
#include "formats/urdf_text.hpp"
#include "simulated_robot.hpp"

namespace inertial {
namespace {

TEST(KdlModelFile, KdlParserLoadsAModelFileWithEveryEffect) {
  const RobotModel robot = LoadUrdf(testing::Example("leg3.urdf"));
  const RobotDynamics model = MakeRobotDynamics(
      robot, ParseEffectList("viscous,coulomb:scale=0.05,offset,armature@knee,spring@hip,rotor@hip:gear=6,payload@foot"));
  const Eigen::VectorXd x = testing::TrueParameters(model, {0.3, 0.2, 0.1}, 5);
  const auto path = testing::TempUrdfPath("kdl.urdf");
  WriteModelUrdf(testing::Example("leg3.urdf"), path.string(), robot, model, SnapshotAt(model, x), "a test");

  KDL::Tree tree;
  ASSERT_TRUE(kdl_parser::treeFromFile(path.string(), tree));
  EXPECT_EQ(tree.getNrOfJoints(), 3u);  // abad, hip, knee (rotors are not URDF joints)
  // Each link's KDL mass is the identified body's (the foot's was merged into the shank: 0 there).
  for (int e = 0; e < 3; ++e) {
    const std::string link = model.bodies()[e].name;
    const auto segment = tree.getSegment(link);
    ASSERT_NE(segment, tree.getSegments().end()) << link;
    EXPECT_NEAR(segment->second.segment.getInertia().getMass(), model.BodyInertia(e, x).mass(), 1e-12) << link;
  }
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace inertial
