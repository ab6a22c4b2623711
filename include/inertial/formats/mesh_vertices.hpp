/// @file mesh_vertices.hpp
/// The vertices of a URDF's mesh files, for the region a link's mass may occupy (model/body_region.hpp):
/// where a link is drawn by a mesh rather than by primitives, and the mesh's file is at hand, its
/// vertices bound the link as a box's corners do.
///
/// Formats, from their published descriptions:
/// - STL, binary (an 80-byte header, a little-endian uint32 triangle count, then 50 bytes per
///   triangle: normal, three vertices as float32, a uint16 attribute) and ASCII ("solid", then
///   "vertex x y z" lines). A file whose size is exactly 84 + 50 n for the count n it states is
///   binary, even when its header starts with "solid" (many exporters write that).
/// - Wavefront OBJ: "v x y z [w]" lines (other lines ignored).
/// COLLADA (.dae) is not read: its vertices only become the link's shape through the scene graph's
/// node transforms and unit, a small interpreter of its own; such a mesh is reported as not read.
///
/// Meshes are named by URI (ResolveMeshUri): `package://PKG/PATH` (ROS), `file://PATH`, or a path
/// relative to the URDF's folder.
///
/// Limits: a mesh file of at most kMaxMeshBytes (a collision mesh is kilobytes to a few MiB, a
/// detailed visual one tens of MiB) and kMaxMeshVertices vertices (an ASCII STL's 3 per triangle).
#pragma once

#include <cstddef>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "inertial/inertia/types.hpp"

namespace inertial {

inline constexpr std::size_t kMaxMeshBytes = std::size_t{128} * 1024 * 1024;
inline constexpr std::size_t kMaxMeshVertices = std::size_t{8} * 1024 * 1024;

/// A mesh that cannot be read: what() names the mesh's source (its path) and says what is wrong.
class MeshError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The vertices of the mesh `bytes` (the format from `source`'s extension, case-insensitive: .stl or
/// .obj), in the file's units. @throws MeshError naming `source` (unknown format, a truncated or
/// malformed file, a vertex that is not a finite number, no vertex, more than kMaxMeshVertices).
std::vector<Vector3> ParseMeshVertices(std::string_view bytes, const std::string& source);

/// Reads the mesh file at `path` (at most kMaxMeshBytes) and parses it. @throws MeshError.
std::vector<Vector3> ReadMeshVertices(const std::string& path);

/// The file a URDF's mesh URI names, if it exists: `file://P` is P; `package://PKG/REST` is the
/// first of DIR/PKG/REST for DIR in $ROS_PACKAGE_PATH, DIR/share/PKG/REST for DIR in
/// $AMENT_PREFIX_PATH, then, from `urdf_directory` up to the root, D/REST where D's own name is PKG
/// and D/PKG/REST (a description package checked out beside or above its URDF); any other URI is
/// a path, relative ones to `urdf_directory` (empty: the working directory).
std::optional<std::string> ResolveMeshUri(const std::string& uri, const std::string& urdf_directory);

/// (x - c)^T P (x - c) <= 1 + this for every point of EnclosingSubset's input (MinimumVolumeEllipsoid
/// stops 1e-4 from the optimum, so its ellipsoid of a subset can leave the whole set's extreme points
/// that far outside).
inline constexpr double kEnclosingSubsetTolerance = 1e-3;

/// A subset of the distinct `points` (at most about 1200) whose smallest enclosing ellipsoid
/// (MinimumVolumeEllipsoid) holds every point within kEnclosingSubsetTolerance: the extreme points
/// along 162 directions, then, while some lie outside, the 64 farthest of those (at most 16 rounds;
/// meshes settle in 1-3, and what a hostile one leaves out lies within the region's 10 % margin). A
/// mesh's hundred thousand vertices cost the region's ellipsoid no more than a box's corners.
std::vector<Vector3> EnclosingSubset(const std::vector<Vector3>& points);

}  // namespace inertial
