// Fuzz harness: a mesh file as a URDF names it (formats/mesh_vertices.hpp). Byte 0 picks the
// format by extension (even: .stl, odd: .obj), the rest is the file; what is accepted must be
// finite vertices, and their enclosing subset must hold every one of them.
#include "fuzz_support.hpp"
#include "inertial/formats/mesh_vertices.hpp"
#include "inertial/inertia/bounding_ellipsoid.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace inertial;
  if (size < 1) return 0;
  const std::string source = (data[0] % 2 == 0) ? "fuzz.stl" : "fuzz.obj";
  std::vector<Vector3> vertices;
  try {
    vertices = ParseMeshVertices(std::string_view(reinterpret_cast<const char*>(data) + 1, size - 1), source);
  } catch (const MeshError&) {
    return 0;
  }
  if (vertices.empty()) fuzz::Fail("a mesh accepted without a vertex");
  for (const Vector3& v : vertices) {
    if (!v.allFinite()) fuzz::Fail("a vertex that is not finite");
  }
  const std::vector<Vector3> subset = EnclosingSubset(vertices);
  BoundingEllipsoid e;
  try {
    e = MinimumVolumeEllipsoid(subset);
  } catch (const std::invalid_argument&) {
    return 0;  // fewer than 4 points, or flat: the region falls back, as documented
  }
  for (const Vector3& v : vertices) {
    const Vector3 d = v - e.center;
    // What EnclosingSubset promises for a mesh that settles is 1 + kEnclosingSubsetTolerance; what it
    // promises for any input is the region's margin (kShapeRegionMargin 0.1: r^2 <= 1.21).
    if (!(d.dot(e.shape_inverse * d) <= 1.21)) fuzz::Fail("a vertex outside its enclosing subset's ellipsoid with the margin");
  }
  return 0;
}
