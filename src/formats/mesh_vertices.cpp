#include "inertial/formats/mesh_vertices.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <utility>

#include "inertial/formats/input_file.hpp"
#include "inertial/formats/number_parsing.hpp"
#include "inertial/inertia/bounding_ellipsoid.hpp"

namespace inertial {
namespace {

std::string Lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

std::string Extension(const std::string& source) { return Lower(std::filesystem::path(source).extension().string()); }

// A mesh refused by its name, read or not.
MeshError UnknownFormat(const std::string& source) {
  return MeshError(source + ": a mesh format this reader does not know ('" + Extension(source) +
                   "'; it reads .stl and .obj, not COLLADA's .dae)");
}

float LittleEndianFloat(const unsigned char* p) {
  const std::uint32_t bits = std::uint32_t{p[0]} | std::uint32_t{p[1]} << 8 | std::uint32_t{p[2]} << 16 |
                             std::uint32_t{p[3]} << 24;
  float f;
  std::memcpy(&f, &bits, sizeof f);
  return f;
}

void AddVertex(const Vector3& v, const std::string& source, const std::string& where, std::vector<Vector3>* out) {
  if (!v.allFinite()) throw MeshError(source + ": " + where + ": a vertex coordinate is not a finite number");
  if (out->size() >= kMaxMeshVertices) {
    throw MeshError(source + ": more than " + std::to_string(kMaxMeshVertices) + " vertices (the limit of a mesh)");
  }
  out->push_back(v);
}

// The triangle count a binary STL states (bytes 80-83), or -1 if it is shorter than its header.
std::int64_t StatedTriangles(std::string_view bytes) {
  if (bytes.size() < 84) return -1;
  const auto* p = reinterpret_cast<const unsigned char*>(bytes.data()) + 80;
  return static_cast<std::int64_t>(std::uint64_t{p[0]} | std::uint64_t{p[1]} << 8 | std::uint64_t{p[2]} << 16 |
                                   std::uint64_t{p[3]} << 24);
}

// An ASCII STL starts with "solid" (after white space).
bool StartsWithSolid(std::string_view bytes) {
  std::size_t i = 0;
  while (i < bytes.size() && std::isspace(static_cast<unsigned char>(bytes[i]))) ++i;
  return bytes.substr(i, 5) == "solid";
}

std::vector<Vector3> BinaryStl(std::string_view bytes, std::size_t n, const std::string& source) {
  if (3 * n > kMaxMeshVertices) {
    throw MeshError(source + ": " + std::to_string(n) + " triangles, more than the limit of " +
                    std::to_string(kMaxMeshVertices / 3));
  }
  std::vector<Vector3> out;
  out.reserve(3 * n);
  const auto* base = reinterpret_cast<const unsigned char*>(bytes.data()) + 84;
  for (std::size_t t = 0; t < n; ++t) {
    const unsigned char* tri = base + 50 * t + 12;  // past the normal
    for (int k = 0; k < 3; ++k) {
      const unsigned char* v = tri + 12 * k;
      AddVertex(Vector3(LittleEndianFloat(v), LittleEndianFloat(v + 4), LittleEndianFloat(v + 8)), source,
                "triangle " + std::to_string(t + 1), &out);
    }
  }
  return out;
}

// The whitespace-separated tokens of one line.
std::vector<std::string_view> Tokens(std::string_view line) {
  std::vector<std::string_view> tokens;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && std::isspace(static_cast<unsigned char>(line[i]))) ++i;
    const std::size_t start = i;
    while (i < line.size() && !std::isspace(static_cast<unsigned char>(line[i]))) ++i;
    if (i > start) tokens.push_back(line.substr(start, i - start));
  }
  return tokens;
}

// Every line starting with `keyword` gives a vertex from its next three tokens (OBJ's "v", ASCII
// STL's "vertex").
std::vector<Vector3> KeywordVertices(std::string_view text, std::string_view keyword, const std::string& source) {
  std::vector<Vector3> out;
  std::size_t line_number = 0;
  std::size_t pos = 0;
  while (pos < text.size()) {
    std::size_t end = text.find('\n', pos);
    if (end == std::string_view::npos) end = text.size();
    const std::string_view line = text.substr(pos, end - pos);
    pos = end + 1;
    ++line_number;
    const std::vector<std::string_view> tokens = Tokens(line);
    if (tokens.empty() || tokens[0] != keyword) continue;
    const std::string where = "line " + std::to_string(line_number);
    if (tokens.size() < 4) throw MeshError(source + ": " + where + ": '" + std::string(keyword) + "' needs three coordinates");
    Vector3 v;
    try {
      for (int k = 0; k < 3; ++k) v[k] = ParseDouble(tokens[static_cast<std::size_t>(k) + 1], where);
    } catch (const InvalidNumber& e) {
      throw MeshError(source + ": " + e.what());
    }
    AddVertex(v, source, where, &out);
  }
  return out;
}

}  // namespace

std::vector<Vector3> ParseMeshVertices(std::string_view bytes, const std::string& source) {
  const std::string ext = Extension(source);
  std::vector<Vector3> vertices;
  if (ext == ".stl") {
    // Binary if the size is exactly what its count states (also with a header that says "solid",
    // as many exporters write); else ASCII if it starts with "solid"; else binary with bytes after
    // its triangles (ignored), if it holds them all.
    const std::int64_t n = StatedTriangles(bytes);
    const std::int64_t size = static_cast<std::int64_t>(bytes.size());
    if (n >= 0 && size == 84 + 50 * n) {
      vertices = BinaryStl(bytes, static_cast<std::size_t>(n), source);
    } else if (StartsWithSolid(bytes)) {
      vertices = KeywordVertices(bytes, "vertex", source);
    } else if (n >= 0 && size > 84 + 50 * n) {
      vertices = BinaryStl(bytes, static_cast<std::size_t>(n), source);
    } else {
      throw MeshError(source + ": neither an ASCII STL (it does not start with 'solid') nor a binary one (" +
                      std::to_string(bytes.size()) + " bytes" +
                      (n < 0 ? ", shorter than the 84-byte header" : ", fewer than the " + std::to_string(84 + 50 * n) +
                                                                            " its " + std::to_string(n) + " triangles take") +
                      ")");
    }
  } else if (ext == ".obj") {
    vertices = KeywordVertices(bytes, "v", source);
  } else {
    throw UnknownFormat(source);
  }
  if (vertices.empty()) throw MeshError(source + ": no vertex");
  return vertices;
}

std::vector<Vector3> ReadMeshVertices(const std::string& path) {
  const std::string ext = Extension(path);
  if (ext != ".stl" && ext != ".obj") throw UnknownFormat(path);  // refused before a byte is read
  std::string bytes;
  try {
    bytes = ReadInputFile(path, "mesh", kMaxMeshBytes);
  } catch (const InputFileError& e) {
    throw MeshError(e.what());
  }
  return ParseMeshVertices(bytes, path);
}

std::optional<std::string> ResolveMeshUri(const std::string& uri, const std::string& urdf_directory) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const auto existing = [&](const fs::path& p) -> std::optional<std::string> {
    if (fs::is_regular_file(p, ec)) return p.string();
    return std::nullopt;
  };
  const std::string package = "package://";
  const std::string file = "file://";
  if (uri.compare(0, file.size(), file) == 0) return existing(uri.substr(file.size()));
  if (uri.compare(0, package.size(), package) != 0) {
    const fs::path p(uri);
    return existing(p.is_absolute() || urdf_directory.empty() ? p : fs::path(urdf_directory) / p);
  }
  const std::string rest_of_uri = uri.substr(package.size());
  const std::size_t slash = rest_of_uri.find('/');
  if (slash == std::string::npos || slash == 0) return std::nullopt;
  const std::string name = rest_of_uri.substr(0, slash);
  const fs::path rest = rest_of_uri.substr(slash + 1);
  const auto each_dir = [](const char* list, auto&& f) -> std::optional<std::string> {
    if (list == nullptr) return std::nullopt;
    std::string s(list);
    std::size_t start = 0;
    while (start <= s.size()) {
      std::size_t end = s.find(':', start);
      if (end == std::string::npos) end = s.size();
      if (end > start) {
        if (auto found = f(fs::path(s.substr(start, end - start)))) return found;
      }
      start = end + 1;
    }
    return std::nullopt;
  };
  if (auto found = each_dir(std::getenv("ROS_PACKAGE_PATH"), [&](const fs::path& d) { return existing(d / name / rest); })) {
    return found;
  }
  if (auto found =
          each_dir(std::getenv("AMENT_PREFIX_PATH"), [&](const fs::path& d) { return existing(d / "share" / name / rest); })) {
    return found;
  }
  fs::path d = fs::absolute(urdf_directory.empty() ? fs::path(".") : fs::path(urdf_directory), ec);
  if (ec) return std::nullopt;
  d = d.lexically_normal();
  for (int depth = 0; depth < 64; ++depth) {
    if (d.filename() == name) {
      if (auto found = existing(d / rest)) return found;
    }
    if (auto found = existing(d / name / rest)) return found;
    if (!d.has_parent_path() || d.parent_path() == d) break;
    d = d.parent_path();
  }
  return std::nullopt;
}

std::vector<Vector3> EnclosingSubset(const std::vector<Vector3>& all_points) {
  // Distinct points only: a binary STL repeats each vertex in every triangle that meets there.
  std::vector<Vector3> points = all_points;
  const auto less = [](const Vector3& a, const Vector3& b) {
    return std::lexicographical_compare(a.data(), a.data() + 3, b.data(), b.data() + 3);
  };
  std::sort(points.begin(), points.end(), less);
  points.erase(std::unique(points.begin(), points.end()), points.end());
  if (points.size() <= 64) return points;
  // 162 directions: the vertices of an icosahedron subdivided twice would do; a golden-angle
  // (Fibonacci) sphere spreads them as evenly and needs no table.
  constexpr int kDirections = 162;
  std::vector<std::size_t> chosen;
  const double golden = M_PI * (3.0 - std::sqrt(5.0));
  for (int k = 0; k < kDirections; ++k) {
    const double z = 1.0 - (2.0 * k + 1.0) / kDirections;
    const double r = std::sqrt(1.0 - z * z);
    const Vector3 u(r * std::cos(golden * k), r * std::sin(golden * k), z);
    std::size_t best = 0;
    for (std::size_t i = 1; i < points.size(); ++i) {
      if (points[i].dot(u) > points[best].dot(u)) best = i;
    }
    chosen.push_back(best);
  }
  std::sort(chosen.begin(), chosen.end());
  chosen.erase(std::unique(chosen.begin(), chosen.end()), chosen.end());
  std::vector<Vector3> subset;
  for (std::size_t i : chosen) subset.push_back(points[i]);
  // The extreme points of 162 directions leave out corners between them by up to about 1 % of the
  // radius: add what lies outside (MinimumVolumeEllipsoid holds its own points exactly) until
  // nothing does (a few rounds; 64 points a round at most).
  for (int round = 0; round < 16; ++round) {
    BoundingEllipsoid e;
    try {
      e = MinimumVolumeEllipsoid(subset);
    } catch (const std::invalid_argument&) {
      return subset;  // flat: the caller's ellipsoid fails on it as on the whole mesh
    }
    std::vector<std::pair<double, std::size_t>> outside;
    for (std::size_t i = 0; i < points.size(); ++i) {
      const Vector3 d = points[i] - e.center;
      const double r2 = d.dot(e.shape_inverse * d);
      // MinimumVolumeEllipsoid stops 1e-4 from the optimum: points on the true ellipsoid may lie
      // that far out of the subset's; beyond 1e-3 (5e-4 of the radius) a point is missing.
      if (r2 > 1.0 + kEnclosingSubsetTolerance) outside.emplace_back(r2, i);
    }
    if (outside.empty()) return subset;
    std::sort(outside.begin(), outside.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
    for (std::size_t k = 0; k < std::min<std::size_t>(outside.size(), 64); ++k) subset.push_back(points[outside[k].second]);
  }
  // Not settled in 16 rounds (the tests' meshes settle in 1-3): the farthest points are in, what
  // is left out lies within the region's margin. All the points instead would make the
  // ellipsoid's cost quadratic in a hostile mesh's vertices.
  return subset;
}

}  // namespace inertial
