#include "inertial/formats/mesh_vertices.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>

#include "inertial/formats/urdf_writer.hpp"
#include "inertial/inertia/bounding_ellipsoid.hpp"
#include "inertial/model/body_region.hpp"
#include "inertial/model/rotation_from_rpy.hpp"
#include "test_support.hpp"
#include "urdf_text.hpp"

namespace inertial {
namespace {

namespace fs = std::filesystem;
using testing::Num;
using testing::TempUrdfPath;
using testing::WriteTextFile;

// The 12 triangles of an axis-aligned box of full sizes `size` about the origin.
std::vector<std::array<Vector3, 3>> BoxTriangles(const Vector3& size) {
  const Vector3 h = size / 2;
  const auto corner = [&](int i) { return Vector3((i & 1) ? h.x() : -h.x(), (i & 2) ? h.y() : -h.y(), (i & 4) ? h.z() : -h.z()); };
  const int faces[6][4] = {{0, 1, 3, 2}, {4, 6, 7, 5}, {0, 4, 5, 1}, {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 5, 7, 3}};
  std::vector<std::array<Vector3, 3>> triangles;
  for (const auto& f : faces) {
    triangles.push_back({corner(f[0]), corner(f[1]), corner(f[2])});
    triangles.push_back({corner(f[0]), corner(f[2]), corner(f[3])});
  }
  return triangles;
}

void PutFloat(float f, std::string* out) {
  std::uint32_t bits;
  std::memcpy(&bits, &f, sizeof bits);
  for (int k = 0; k < 4; ++k) out->push_back(static_cast<char>((bits >> (8 * k)) & 0xff));
}

// A binary STL written from the format's description; `header` starts the 80-byte header.
std::string BinaryStl(const std::vector<std::array<Vector3, 3>>& triangles, const std::string& header = "inertial test") {
  std::string s = header;
  s.resize(80, ' ');
  const auto n = static_cast<std::uint32_t>(triangles.size());
  for (int k = 0; k < 4; ++k) s.push_back(static_cast<char>((n >> (8 * k)) & 0xff));
  for (const auto& t : triangles) {
    for (int k = 0; k < 3; ++k) PutFloat(0.0f, &s);  // normal: readers must not need it
    for (const Vector3& v : t) {
      for (int k = 0; k < 3; ++k) PutFloat(static_cast<float>(v[k]), &s);
    }
    s.append(2, '\0');
  }
  return s;
}

std::string AsciiStl(const std::vector<std::array<Vector3, 3>>& triangles) {
  std::string s = "solid box\n";
  for (const auto& t : triangles) {
    s += "  facet normal 0 0 0\n    outer loop\n";
    for (const Vector3& v : t) s += "      vertex " + Num(v.x()) + " " + Num(v.y()) + " " + Num(v.z()) + "\n";
    s += "    endloop\n  endfacet\n";
  }
  return s + "endsolid box\n";
}

std::string Obj(const std::vector<std::array<Vector3, 3>>& triangles) {
  std::string s = "# box\no box\n";
  for (const auto& t : triangles) {
    for (const Vector3& v : t) s += "v " + Num(v.x()) + " " + Num(v.y()) + " " + Num(v.z()) + "\n";
  }
  return s + "f 1 2 3\n";
}

std::string MeshErrorOf(std::string_view bytes, const std::string& source) {
  try {
    ParseMeshVertices(bytes, source);
  } catch (const MeshError& e) {
    return e.what();
  }
  return "";
}

TEST(MeshVertices, ReadsBinaryAsciiStlAndObjAlike) {
  const Vector3 size(0.3, 0.1, 0.05);
  const auto triangles = BoxTriangles(size);
  for (const auto& [bytes, name] : {std::pair{BinaryStl(triangles), std::string("box.stl")},
                                    std::pair{BinaryStl(triangles, "solid but binary"), std::string("box.STL")},
                                    std::pair{AsciiStl(triangles), std::string("box.stl")},
                                    std::pair{Obj(triangles), std::string("box.obj")}}) {
    SCOPED_TRACE(name + ": " + bytes.substr(0, 16));
    const std::vector<Vector3> v = ParseMeshVertices(bytes, name);
    ASSERT_EQ(v.size(), 36u);
    for (std::size_t i = 0; i < v.size(); ++i) {
      // float32 in the binary files: 1e-7 relative
      EXPECT_LT((v[i] - triangles[i / 3][i % 3]).norm(), 1e-7) << i;
    }
  }
}

TEST(MeshVertices, RefusesMalformedMeshesNamingThemAndWhatIsWrong) {
  const std::string good = BinaryStl(BoxTriangles(Vector3(1, 1, 1)));
  std::string truncated = good.substr(0, good.size() - 7);
  EXPECT_NE(MeshErrorOf(truncated, "m/part.stl").find("m/part.stl: neither an ASCII STL (it does not start with 'solid') nor a binary one (677 bytes, fewer than the 684 its 12 triangles take)"), std::string::npos)
      << MeshErrorOf(truncated, "m/part.stl");
  EXPECT_NE(MeshErrorOf("solid x\n vertex 1 2\n", "a.stl").find("a.stl: line 2: 'vertex' needs three coordinates"),
            std::string::npos);
  EXPECT_NE(MeshErrorOf("v 1 nan 2\n", "a.obj").find("a.obj"), std::string::npos);
  EXPECT_NE(MeshErrorOf("v 1 x 2\n", "a.obj").find("line 1"), std::string::npos);
  EXPECT_NE(MeshErrorOf("# nothing\n", "a.obj").find("a.obj: no vertex"), std::string::npos);
  EXPECT_NE(MeshErrorOf("<COLLADA/>", "arm.dae").find("not COLLADA's .dae"), std::string::npos);
  std::string nan_stl = BinaryStl({{Vector3(0, 0, 0), Vector3(1, 0, 0), Vector3(std::nan(""), 0, 0)}});
  EXPECT_NE(MeshErrorOf(nan_stl, "n.stl").find("n.stl: triangle 1: a vertex coordinate is not a finite number"),
            std::string::npos)
      << MeshErrorOf(nan_stl, "n.stl");
  try {
    ReadMeshVertices("/nonexistent/inertial/part.stl");
    ADD_FAILURE() << "no error";
  } catch (const MeshError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/inertial/part.stl"), std::string::npos) << e.what();
  }
}

TEST(MeshVertices, ResolvesPackageFileAndRelativeUris) {
  const fs::path root = TempUrdfPath("meshes");
  fs::create_directories(root / "ws" / "arm_description" / "meshes");
  fs::create_directories(root / "ws" / "arm_description" / "urdf");
  fs::create_directories(root / "elsewhere" / "tool_pkg" / "meshes");
  fs::create_directories(root / "ament" / "share" / "gripper" / "meshes");
  const fs::path part = root / "ws" / "arm_description" / "meshes" / "l1.stl";
  WriteTextFile(part, "solid\n");
  WriteTextFile(root / "elsewhere" / "tool_pkg" / "meshes" / "t.stl", "solid\n");
  WriteTextFile(root / "ament" / "share" / "gripper" / "meshes" / "g.stl", "solid\n");
  const std::string urdf_dir = (root / "ws" / "arm_description" / "urdf").string();
  // the package folder found above the URDF, by its own name
  const auto found = ResolveMeshUri("package://arm_description/meshes/l1.stl", urdf_dir);
  ASSERT_TRUE(found.has_value());
  EXPECT_TRUE(fs::equivalent(*found, part));
  // relative to the URDF, and file://
  ASSERT_TRUE(ResolveMeshUri("../meshes/l1.stl", urdf_dir).has_value());
  const auto by_file_uri = ResolveMeshUri("file://" + part.string(), "");
  ASSERT_TRUE(by_file_uri.has_value());
  EXPECT_TRUE(fs::equivalent(*by_file_uri, part));
  EXPECT_FALSE(ResolveMeshUri("package://tool_pkg/meshes/t.stl", urdf_dir).has_value());
  EXPECT_FALSE(ResolveMeshUri("package://arm_description/meshes/missing.stl", urdf_dir).has_value());
  EXPECT_FALSE(ResolveMeshUri("package://", urdf_dir).has_value());
  // $ROS_PACKAGE_PATH and $AMENT_PREFIX_PATH
  const char* old_ros = std::getenv("ROS_PACKAGE_PATH");
  const char* old_ament = std::getenv("AMENT_PREFIX_PATH");
  const std::string saved_ros = old_ros ? old_ros : "", saved_ament = old_ament ? old_ament : "";
  setenv("ROS_PACKAGE_PATH", ("/nonexistent:" + (root / "elsewhere").string()).c_str(), 1);
  setenv("AMENT_PREFIX_PATH", (root / "ament").string().c_str(), 1);
  EXPECT_TRUE(ResolveMeshUri("package://tool_pkg/meshes/t.stl", urdf_dir).has_value());
  EXPECT_TRUE(ResolveMeshUri("package://gripper/meshes/g.stl", urdf_dir).has_value());
  if (old_ros) setenv("ROS_PACKAGE_PATH", saved_ros.c_str(), 1); else unsetenv("ROS_PACKAGE_PATH");
  if (old_ament) setenv("AMENT_PREFIX_PATH", saved_ament.c_str(), 1); else unsetenv("AMENT_PREFIX_PATH");
  fs::remove_all(root);
}

TEST(MeshVertices, EnclosingSubsetHoldsEveryPointAndGivesTheWholeSetsEllipsoid) {
  testing::Rng rng(11);
  // A lumpy blob: 6000 points in a rotated, stretched ball with bumps (a mesh's vertices).
  const Matrix3 R = RotationFromRpy(Vector3(0.4, -0.7, 1.1));
  std::vector<Vector3> points;
  for (int i = 0; i < 6000; ++i) {
    const double ux = rng.Normal();
    const double uy = rng.Normal();
    const double uz = rng.Normal();
    Vector3 u(ux, uy, uz);
    u.normalize();
    const double r = 1.0 + 0.15 * std::sin(5 * u.x()) * std::cos(3 * u.y());
    points.push_back(R * Vector3(0.3, 0.12, 0.05).cwiseProduct(r * u) + Vector3(0.1, 0, -0.2));
  }
  const std::vector<Vector3> subset = EnclosingSubset(points);
  EXPECT_LT(subset.size(), 1200u);
  const BoundingEllipsoid from_subset = MinimumVolumeEllipsoid(subset);
  for (const Vector3& p : points) ASSERT_LE((p - from_subset.center).dot(from_subset.shape_inverse * (p - from_subset.center)), 1.0 + kEnclosingSubsetTolerance);
  // The same ellipsoid as from all 6000 points (Khachiyan's tolerance 1e-4: volumes within 1e-3).
  const BoundingEllipsoid from_all = MinimumVolumeEllipsoid(points);
  EXPECT_NEAR(from_subset.Volume() / from_all.Volume(), 1.0, 1e-3);
}

// A one-link robot whose link is drawn by `collision` (URDF text inside <collision>).
std::string OneLinkRobot(const std::string& collision) {
  using testing::InertialXml;
  using testing::JointXml;
  using testing::LinkXml;
  const std::string inertial = InertialXml(2.0, Vector3(0.1, 0, 0), Vector3::Zero(), Matrix3(Vector3(0.002, 0.01, 0.01).asDiagonal()));
  return testing::RobotXml("one", LinkXml("base") + LinkXml("arm", inertial + "<collision>" + collision + "</collision>") +
                                      JointXml("j", "revolute", "base", "arm", Vector3::Zero(), Vector3::Zero(), Vector3::UnitZ()));
}

TEST(MeshVertices, AMeshAtHandDrawsTheLinksRegionAsTheSamePrimitiveDoes) {
  const fs::path root = TempUrdfPath("mesh_robot");
  fs::create_directories(root / "one_description" / "meshes");
  fs::create_directories(root / "one_description" / "urdf");
  // The mesh: a box of 0.2 x 0.1 x 0.05 drawn in millimetres (scale 0.001), posed at xyz/rpy.
  WriteTextFile(root / "one_description" / "meshes" / "arm.stl", BinaryStl(BoxTriangles(Vector3(200, 100, 50))));
  const std::string pose = "<origin xyz=\"0.12 0.01 -0.02\" rpy=\"0.3 0.2 -0.5\"/>";
  const fs::path with_mesh = root / "one_description" / "urdf" / "mesh.urdf";
  WriteTextFile(with_mesh, OneLinkRobot(pose + "<geometry><mesh filename=\"package://one_description/meshes/arm.stl\" "
                                               "scale=\"0.001 0.001 0.001\"/></geometry>"));
  const fs::path with_box = root / "one_description" / "urdf" / "box.urdf";
  WriteTextFile(with_box, OneLinkRobot(pose + "<geometry><box size=\"0.2 0.1 0.05\"/></geometry>"));
  const RobotModel mesh = LoadUrdf(with_mesh.string());
  const RobotModel box = LoadUrdf(with_box.string());
  EXPECT_TRUE(mesh.unread_meshes.empty());
  EXPECT_EQ(mesh.body_shape_meshes[0], 0);
  const BodyRegion a = RegionOfPoints(mesh.body_shape_points[0], kShapeRegionMargin, RegionSource::kShape);
  const BodyRegion b = RegionOfPoints(box.body_shape_points[0], kShapeRegionMargin, RegionSource::kShape);
  EXPECT_LT((a.ellipsoid.center - b.ellipsoid.center).norm(), 1e-6);
  EXPECT_LT((a.ellipsoid.shape_inverse - b.ellipsoid.shape_inverse).norm() / b.ellipsoid.shape_inverse.norm(), 1e-5);

  // A mesh that is not at hand is named, and the link has no drawn points (its segment region).
  const fs::path missing = root / "one_description" / "urdf" / "missing.urdf";
  WriteTextFile(missing, OneLinkRobot("<geometry><mesh filename=\"package://one_description/meshes/gone.stl\"/></geometry>"));
  const RobotModel gone = LoadUrdf(missing.string());
  ASSERT_EQ(gone.unread_meshes.size(), 1u);
  EXPECT_EQ(gone.unread_meshes[0], "arm: package://one_description/meshes/gone.stl (not found)");
  EXPECT_TRUE(gone.body_shape_points[0].empty());
  EXPECT_EQ(gone.body_shape_meshes[0], 1);
  fs::remove_all(root);
}

TEST(MeshVertices, ABodyPartlyUndrawnGetsNoDrawnPoints) {
  // The link "arm" drawn by a box, a fixed "tool" with 1 kg and no collision shape merged into it:
  // the box bounds only part of the body, so it gets no drawn points (its segment region instead).
  using testing::InertialXml;
  using testing::JointXml;
  using testing::LinkXml;
  const std::string arm = LinkXml("arm", InertialXml(2.0, Vector3(0.1, 0, 0), Vector3::Zero(), Matrix3(Vector3(0.002, 0.01, 0.01).asDiagonal())) +
                                             "<collision><geometry><box size=\"0.2 0.1 0.1\"/></geometry></collision>");
  const std::string tool = LinkXml("tool", InertialXml(1.0, Vector3::Zero(), Vector3::Zero(), Matrix3(Vector3(0.001, 0.001, 0.001).asDiagonal())));
  const std::string joints = JointXml("j", "revolute", "base", "arm") + JointXml("t", "fixed", "arm", "tool", Vector3(0.4, 0, 0));
  const RobotModel with_tool = ParseUrdf(testing::RobotXml("r", LinkXml("base") + arm + tool + joints), "<string>");
  EXPECT_TRUE(with_tool.body_shape_points[0].empty());
  // Without the tool's mass the box draws the body.
  const std::string massless_tool = LinkXml("tool");
  const RobotModel drawn = ParseUrdf(testing::RobotXml("r", LinkXml("base") + arm + massless_tool + joints), "<string>");
  EXPECT_EQ(drawn.body_shape_points[0].size(), 8u);
  // Text without a folder reads no mesh, and says so.
  const RobotModel text = ParseUrdf(OneLinkRobot("<geometry><mesh filename=\"arm.stl\"/></geometry>"), "<string>");
  ASSERT_EQ(text.unread_meshes.size(), 1u);
  EXPECT_NE(text.unread_meshes[0].find("meshes not looked for"), std::string::npos) << text.unread_meshes[0];
}

TEST(MeshVertices, AModelFileWrittenElsewhereStillFindsItsMeshes) {
  const fs::path root = TempUrdfPath("mesh_writer");
  fs::create_directories(root / "desc" / "meshes");
  fs::create_directories(root / "out");
  WriteTextFile(root / "desc" / "meshes" / "arm.obj", Obj(BoxTriangles(Vector3(0.2, 0.1, 0.05))));
  const fs::path in = root / "desc" / "robot.urdf";
  WriteTextFile(in, OneLinkRobot("<geometry><mesh filename=\"meshes/arm.obj\"/></geometry>"));
  const RobotModel original = LoadUrdf(in.string());
  ASSERT_TRUE(original.unread_meshes.empty());
  const fs::path out = root / "out" / "fit.urdf";
  WriteUrdfModel(in.string(), out.string(), UrdfModelChanges{});
  const RobotModel written = LoadUrdf(out.string());
  EXPECT_TRUE(written.unread_meshes.empty()) << (written.unread_meshes.empty() ? "" : written.unread_meshes[0]);
  EXPECT_EQ(written.body_shape_points[0], original.body_shape_points[0]);
  // Written beside the input, the relative name stays as it was.
  const fs::path beside = root / "desc" / "fit.urdf";
  WriteUrdfModel(in.string(), beside.string(), UrdfModelChanges{});
  EXPECT_NE(testing::ReadTextFile(beside).find("filename=\"meshes/arm.obj\""), std::string::npos);
  fs::remove_all(root);
}

}  // namespace
}  // namespace inertial
