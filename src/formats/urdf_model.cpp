#include "inertial/formats/urdf_model.hpp"

#include <console_bridge/console.h>
#include <tinyxml2.h>
#include <urdf_parser/urdf_parser.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstring>
#include <map>
#include <filesystem>
#include <optional>
#include <mutex>

#include "inertial/formats/input_file.hpp"
#include "inertial/formats/mesh_vertices.hpp"
#include "inertial/inertia/consistency.hpp"
#include "inertial/model/body_region.hpp"
#include "inertial/formats/number_parsing.hpp"
#include "inertial/model/number_text.hpp"
#include "urdf_effects.hpp"
#include "urdf_joint_limits.hpp"
#include "xml_error.hpp"

namespace inertial {
namespace {

// Collects the errors urdfdom logs through console_bridge while it parses; warnings go on to the
// handler that was installed before.
class CapturingLogHandler : public console_bridge::OutputHandler {
 public:
  explicit CapturingLogHandler(console_bridge::OutputHandler* previous) : previous_(previous) {}
  void log(const std::string& text, console_bridge::LogLevel level, const char* filename, int line) override {
    if (level >= console_bridge::CONSOLE_BRIDGE_LOG_ERROR) {
      errors_.push_back(text);
    } else if (level == console_bridge::CONSOLE_BRIDGE_LOG_WARN && previous_ != nullptr) {
      previous_->log(text, level, filename, line);
    }
  }
  const std::vector<std::string>& errors() const { return errors_; }

 private:
  console_bridge::OutputHandler* previous_;
  std::vector<std::string> errors_;
};

// console_bridge's output handler is process-wide: one capture at a time.
std::mutex& LogCaptureMutex() {
  static std::mutex mutex;
  return mutex;
}

std::string Join(const std::vector<std::string>& items, const std::string& separator) {
  std::string out;
  for (std::size_t k = 0; k < items.size(); ++k) out += (k ? separator : "") + items[k];
  return out;
}

// Runs urdfdom on the text, turning a null model or any logged error into a UrdfError.
urdf::ModelInterfaceSharedPtr ParseWithUrdfdom(const std::string& xml, const std::string& source) {
  const std::lock_guard<std::mutex> lock(LogCaptureMutex());
  CapturingLogHandler handler(console_bridge::getOutputHandler());
  console_bridge::useOutputHandler(&handler);
  urdf::ModelInterfaceSharedPtr model;
  std::string exception_text;
  try {
    model = urdf::parseURDF(xml);
  } catch (const std::exception& e) {
    exception_text = e.what();
  }
  console_bridge::restorePreviousOutputHandler();
  std::vector<std::string> errors = handler.errors();
  if (!exception_text.empty()) errors.push_back(exception_text);
  if (!model || !errors.empty()) {
    throw UrdfError(source + ": is not a valid URDF" + (errors.empty() ? std::string() : ": " + Join(errors, "; ")));
  }
  return model;
}

// File order of the <link> and <joint> elements (urdfdom keeps them in maps sorted by name).
struct FileOrder {
  std::vector<std::string> links;
  std::vector<std::string> joints;
};

// The numeric attributes of the elements urdfdom reads, with how many numbers each holds (0: one
// or more, as a mesh's scale may be given).
const std::map<std::string, std::map<std::string, int>>& NumericAttributes() {
  static const std::map<std::string, std::map<std::string, int>> table = {
      {"origin", {{"xyz", 3}, {"rpy", 3}}},
      {"mass", {{"value", 1}}},
      {"inertia", {{"ixx", 1}, {"ixy", 1}, {"ixz", 1}, {"iyy", 1}, {"iyz", 1}, {"izz", 1}}},
      {"axis", {{"xyz", 3}}},
      {"limit", {{"lower", 1}, {"upper", 1}, {"effort", 1}, {"velocity", 1}}},
      {"dynamics", {{"damping", 1}, {"friction", 1}}},
      {"safety_controller", {{"soft_lower_limit", 1}, {"soft_upper_limit", 1}, {"k_position", 1}, {"k_velocity", 1}}},
      {"calibration", {{"rising", 1}, {"falling", 1}, {"reference_position", 1}}},
      {"mimic", {{"multiplier", 1}, {"offset", 1}}},
      {"box", {{"size", 3}}},
      {"cylinder", {{"radius", 1}, {"length", 1}}},
      {"sphere", {{"radius", 1}}},
      {"capsule", {{"radius", 1}, {"length", 1}}},
      {"mesh", {{"scale", 3}}},
      {"color", {{"rgba", 4}}},
  };
  return table;
}

// The unit of the attributes bounded by kMaxUrdfLength: positions of frames (origins of joints, of
// COMs, of visuals and collisions) and sizes of shapes [m], and joint limits [m or rad]; nullptr
// for the others.
const char* BoundedUnit(const std::string& element, const std::string& attribute) {
  if ((element == "origin" && attribute == "xyz") || (element == "box" && attribute == "size") ||
      ((element == "cylinder" || element == "capsule") && (attribute == "radius" || attribute == "length")) ||
      (element == "sphere" && attribute == "radius")) {
    return "m";
  }
  if (element == "limit" && (attribute == "lower" || attribute == "upper")) return "m or rad";
  return nullptr;
}

// Checks the subtree of an element urdfdom reads before urdfdom sees it: urdfdom (through
// console_bridge) hands some attribute text to a printf-style logger as the format itself, so a
// '%' in it reads or writes memory. No attribute there may hold a '%', and every numeric attribute
// must hold exactly its finite numbers (number_parsing.hpp); anything else is refused naming the
// file, the element (with its line) and the attribute.
void ValidateForUrdfdom(const tinyxml2::XMLElement& e, const std::string& source, const std::string& owner = "") {
  const std::string where =
      source + ": " + owner + "<" + std::string(e.Name()) + "> (line " + std::to_string(e.GetLineNum()) + ")";
  const auto numeric = NumericAttributes().find(e.Name());
  for (const tinyxml2::XMLAttribute* a = e.FirstAttribute(); a != nullptr; a = a->Next()) {
    const std::string value = a->Value();
    if (value.find('%') != std::string::npos) {
      throw UrdfError(where + ": attribute '" + a->Name() + "' holds a '%', which no URDF value needs");
    }
    if (numeric == NumericAttributes().end()) continue;
    const auto count = numeric->second.find(a->Name());
    if (count == numeric->second.end()) continue;
    std::vector<double> numbers;
    try {
      const std::string what = std::string("attribute '") + a->Name() + "'";
      numbers = count->second == 1 ? std::vector<double>{ParseDouble(value, what)} : ParseNumberList(value, what);
    } catch (const InvalidNumber& err) {
      throw UrdfError(where + ": " + err.what());
    }
    if (static_cast<int>(numbers.size()) != count->second) {
      throw UrdfError(where + ": attribute '" + a->Name() + "' holds " + std::to_string(numbers.size()) +
                      " numbers, " + std::to_string(count->second) + " expected");
    }
    if (const char* unit = BoundedUnit(e.Name(), a->Name())) {
      for (const double x : numbers) {
        if (std::abs(x) > kMaxUrdfLength) {
          throw UrdfError(where + ": attribute '" + a->Name() + "' holds " + FormatNumberExact(x) + " " + unit + ", beyond the " +
                          FormatNumberExact(kMaxUrdfLength) + " " + unit + " of any robot (a length in millimetres?)");
        }
      }
    }
  }
  for (const tinyxml2::XMLElement* c = e.FirstChildElement(); c != nullptr; c = c->NextSiblingElement()) {
    ValidateForUrdfdom(*c, source, owner);
  }
}

// The joints must form a tree before urdfdom links them: a joint whose parent is its own child, a
// link with two parent joints, or a loop of joints makes urdfdom's links hold each other by shared
// pointers, which leak when it then refuses the file (a fuzzed URDF found it).
void CheckJointGraph(const tinyxml2::XMLElement& robot, const std::string& source) {
  std::map<std::string, std::pair<std::string, std::string>> parent_of;  // child link -> {parent link, joint}
  for (const tinyxml2::XMLElement* j = robot.FirstChildElement("joint"); j; j = j->NextSiblingElement("joint")) {
    const tinyxml2::XMLElement* parent = j->FirstChildElement("parent");
    const tinyxml2::XMLElement* child = j->FirstChildElement("child");
    const char* parent_link = parent != nullptr ? parent->Attribute("link") : nullptr;
    const char* child_link = child != nullptr ? child->Attribute("link") : nullptr;
    if (parent_link == nullptr || child_link == nullptr) continue;  // urdfdom names what is missing
    const std::string joint = j->Attribute("name") != nullptr ? j->Attribute("name") : "";
    const std::string where = source + ": joint '" + joint + "' (line " + std::to_string(j->GetLineNum()) + ")";
    if (std::strcmp(parent_link, child_link) == 0) {
      throw UrdfError(where + ": link '" + std::string(child_link) + "' is both its parent and its child");
    }
    const auto [it, inserted] = parent_of.emplace(child_link, std::make_pair(std::string(parent_link), joint));
    if (!inserted) {
      throw UrdfError(where + ": link '" + std::string(child_link) + "' is already the child of joint '" +
                      it->second.second + "'; a link has one parent joint");
    }
  }
  for (const auto& [start, unused] : parent_of) {
    std::string link = start;
    for (std::size_t steps = 0; steps <= parent_of.size(); ++steps) {
      const auto up = parent_of.find(link);
      if (up == parent_of.end()) break;
      link = up->second.first;
      if (link == start) {
        throw UrdfError(source + ": the joints form a loop through link '" + start + "' (joint '" + up->second.second +
                        "'); a URDF describes a tree");
      }
    }
  }
}

// The text of an XML declaration between "<?" and "?>" by XML 1.0's production 23:
// xml S version="1.x" [S encoding="Name"] [S standalone="yes|no"] [S], either quote. A scan, not a
// std::regex: libstdc++'s regex recurses once per character and overflowed the stack on a long
// declaration (found by tests/fuzz/urdf_fuzz.cpp).
bool IsXmlDeclaration(const std::string& text) {
  std::size_t at = 0;
  const auto space = [&] {
    const std::size_t from = at;
    while (at < text.size() && (text[at] == ' ' || text[at] == '\t' || text[at] == '\r' || text[at] == '\n')) ++at;
    return at > from;
  };
  // S name S? = S? quoted value, the value checked by `valid`.
  const auto attribute = [&](const std::string& name, const auto& valid) {
    const std::size_t from = at;
    if (!space() || text.compare(at, name.size(), name) != 0) {
      at = from;
      return false;
    }
    at += name.size();
    space();
    if (at >= text.size() || text[at] != '=') return at = from, false;
    ++at;
    space();
    if (at >= text.size() || (text[at] != '"' && text[at] != '\'')) return at = from, false;
    const std::size_t close = text.find(text[at], at + 1);
    if (close == std::string::npos || !valid(text.substr(at + 1, close - at - 1))) return at = from, false;
    at = close + 1;
    return true;
  };
  const auto version = [](const std::string& v) {
    return v.size() > 2 && v.compare(0, 2, "1.") == 0 &&
           std::all_of(v.begin() + 2, v.end(), [](char c) { return c >= '0' && c <= '9'; });
  };
  const auto encoding = [](const std::string& v) {
    return !v.empty() && std::isalpha(static_cast<unsigned char>(v[0])) &&
           std::all_of(v.begin(), v.end(), [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '_' || c == '-'; });
  };
  const auto standalone = [](const std::string& v) { return v == "yes" || v == "no"; };
  if (text.compare(0, 3, "xml") != 0) return false;
  at = 3;
  if (!attribute("version", version)) return false;
  attribute("encoding", encoding);
  attribute("standalone", standalone);
  space();
  return at == text.size();
}

// tinyxml2 reads every "<?...?>" before the root element as one declaration node, whatever it holds
// (it refuses them anywhere else). The XML declaration ("<?xml version=... ?>", first in the file)
// must have its grammar (XML 1.0, production 23), and no other processing instruction may hold a
// '<': "<?xml " with 100,000 nested elements before its "?>" is one node to tinyxml2 and 100,000
// elements to other XML readers (issue 35).
void CheckDeclarations(const tinyxml2::XMLDocument& doc, const std::string& source) {
  for (const tinyxml2::XMLNode* n = doc.FirstChild(); n != nullptr; n = n->NextSibling()) {
    const tinyxml2::XMLDeclaration* d = n->ToDeclaration();
    if (d == nullptr) continue;
    const std::string text = d->Value();
    const std::string where =
        source + ": is not a valid URDF: the processing instruction at line " + std::to_string(d->GetLineNum());
    const bool xml = text.compare(0, 3, "xml") == 0 && (text.size() == 3 || std::isspace(static_cast<unsigned char>(text[3])));
    if (xml && (n != doc.FirstChild() || !IsXmlDeclaration(text))) {
      throw UrdfError(where + " is not an XML declaration (<?xml version=\"1.0\" encoding=\"...\"?>, first in the file)");
    }
    if (text.find('<') != std::string::npos) throw UrdfError(where + " holds a '<' (an element inside \"<?...?>\")");
  }
}

// Prints what urdfdom needs of an element: elements, attributes and text; comments and unknown
// nodes ("<!...>") left out.
class UrdfdomPrinter : public tinyxml2::XMLPrinter {
 public:
  UrdfdomPrinter() : tinyxml2::XMLPrinter(nullptr, /*compact=*/true) {}
  bool Visit(const tinyxml2::XMLComment&) override { return true; }
  bool Visit(const tinyxml2::XMLUnknown&) override { return true; }
};

// The first tag with more than kMaxUrdfAttributes '=' outside quoted values (each attribute needs
// one), found by a scan of the text before any XML parser runs; its line, or 0 if none. Comments,
// CDATA sections, declarations and "<!...>" are skipped as XML readers skip them.
int LineOfTagWithTooManyAttributes(const std::string& xml) {
  int line = 1;
  std::size_t at = 0;
  const auto skip_to = [&](const char* end) {
    const std::size_t found = xml.find(end, at);
    const std::size_t stop = found == std::string::npos ? xml.size() : found + std::strlen(end);
    line += static_cast<int>(std::count(xml.begin() + static_cast<std::ptrdiff_t>(at), xml.begin() + static_cast<std::ptrdiff_t>(stop), '\n'));
    at = stop;
  };
  while (at < xml.size()) {
    if (xml[at] != '<') {
      if (xml[at] == '\n') ++line;
      ++at;
      continue;
    }
    if (xml.compare(at, 4, "<!--") == 0) {
      skip_to("-->");
    } else if (xml.compare(at, 9, "<![CDATA[") == 0) {
      skip_to("]]>");
    } else if (xml.compare(at, 2, "<?") == 0) {
      skip_to("?>");
    } else if (xml.compare(at, 2, "<!") == 0) {
      skip_to(">");
    } else {
      const int tag_line = line;
      int equals = 0;
      char quote = 0;
      for (++at; at < xml.size() && (quote != 0 || xml[at] != '>'); ++at) {
        const char c = xml[at];
        if (c == '\n') ++line;
        if (quote != 0) {
          if (c == quote) quote = 0;
        } else if (c == '"' || c == '\'') {
          quote = c;
        } else if (c == '=' && ++equals > kMaxUrdfAttributes) {
          return tag_line;
        }
      }
    }
  }
  return 0;
}

// Parses and checks the URDF with tinyxml2 into *doc and returns its <robot>. tinyxml2 refuses
// nesting deeper than TINYXML2_MAX_ELEMENT_DEPTH (100) levels, which no URDF needs.
const tinyxml2::XMLElement& ParseRobotXml(const std::string& xml, const std::string& source, tinyxml2::XMLDocument* doc) {
  if (xml.size() > kMaxUrdfBytes) throw UrdfError(TooLargeText(source, "URDF", xml.size(), kMaxUrdfBytes));
  if (const int line = LineOfTagWithTooManyAttributes(xml)) {
    throw UrdfError(source + ": is not a valid URDF: the tag at line " + std::to_string(line) + " has more than " +
                    std::to_string(kMaxUrdfAttributes) + " attributes");
  }
  if (doc->Parse(xml.c_str(), xml.size()) != tinyxml2::XML_SUCCESS) {
    throw UrdfError(source + ": is not a valid URDF: " + detail::DescribeXmlError(*doc));
  }
  CheckDeclarations(*doc, source);
  const tinyxml2::XMLElement* robot = doc->RootElement();
  if (robot == nullptr || std::strcmp(robot->Name(), "robot") != 0) {
    throw UrdfError(source + ": is not a valid URDF: the root element is " +
                    (robot == nullptr ? std::string("missing") : "<" + std::string(robot->Name()) + ">") +
                    ", not <robot>");
  }
  for (const tinyxml2::XMLAttribute* a = robot->FirstAttribute(); a != nullptr; a = a->Next()) {
    if (std::string(a->Value()).find('%') != std::string::npos) {
      throw UrdfError(source + ": <robot> attribute '" + a->Name() + "' holds a '%', which no URDF value needs");
    }
  }
  int links = 0, joints = 0;
  for (const tinyxml2::XMLElement* e = robot->FirstChildElement(); e; e = e->NextSiblingElement()) {
    links += std::strcmp(e->Name(), "link") == 0;
    joints += std::strcmp(e->Name(), "joint") == 0;
  }
  if (links > kMaxUrdfLinks || joints > kMaxUrdfLinks) {
    throw UrdfError(source + ": has " + std::to_string(links) + " links and " + std::to_string(joints) +
                    " joints, more than the " + std::to_string(kMaxUrdfLinks) + " of any robot");
  }
  for (const tinyxml2::XMLElement* e = robot->FirstChildElement(); e; e = e->NextSiblingElement()) {
    const std::string name = e->Name();
    if (name == "link" || name == "joint" || name == "material") {
      const char* element_name = e->Attribute("name");
      ValidateForUrdfdom(*e, source, element_name != nullptr ? name + " '" + element_name + "': " : "");
    }
  }
  CheckJointGraph(*robot, source);
  return *robot;
}

// What urdfdom parses: the <robot> element tinyxml2 read and checked, printed again, and nothing
// else. urdfdom parses with the old TinyXML, which recurses once per level of nesting with no limit
// and reads a declaration differently from tinyxml2: "<?xml " followed by 100,000 nested elements
// and "?>" was one declaration node to tinyxml2 and 100,000 levels of recursion (a stack overflow)
// to TinyXML (issue 35). The printed element has anything outside <robot> dropped, and inside it
// only elements, attributes and text (UrdfdomPrinter): its nesting is what tinyxml2 counted.
std::string RobotElementText(const tinyxml2::XMLElement& robot) {
  UrdfdomPrinter printer;
  robot.Accept(&printer);
  return std::string(printer.CStr(), static_cast<std::size_t>(printer.CStrSize() - 1));
}

FileOrder ReadFileOrder(const tinyxml2::XMLElement& robot) {
  FileOrder order;
  for (const tinyxml2::XMLElement* e = robot.FirstChildElement("link"); e; e = e->NextSiblingElement("link")) {
    if (const char* name = e->Attribute("name")) order.links.emplace_back(name);
  }
  for (const tinyxml2::XMLElement* e = robot.FirstChildElement("joint"); e; e = e->NextSiblingElement("joint")) {
    if (const char* name = e->Attribute("name")) order.joints.emplace_back(name);
  }
  return order;
}

Matrix3 RotationOf(const urdf::Rotation& r) {
  return Eigen::Quaterniond(r.w, r.x, r.y, r.z).normalized().toRotationMatrix();
}

Vector3 VectorOf(const urdf::Vector3& v) { return Vector3(v.x, v.y, v.z); }

// a * b for poses (a: B in A, b: C in B) -> C in A.
SpatialTransform Compose(const SpatialTransform& a, const SpatialTransform& b) {
  SpatialTransform c;
  c.R_AB = a.R_AB * b.R_AB;
  c.p_AB = a.R_AB * b.p_AB + a.p_AB;
  return c;
}

std::string JointTypeName(int type) {
  switch (type) {
    case urdf::Joint::REVOLUTE: return "revolute";
    case urdf::Joint::CONTINUOUS: return "continuous";
    case urdf::Joint::PRISMATIC: return "prismatic";
    case urdf::Joint::FIXED: return "fixed";
    case urdf::Joint::FLOATING: return "floating";
    case urdf::Joint::PLANAR: return "planar";
    default: return "unknown";
  }
}

// Rejects what the tree cannot represent; returns the joint frame in its parent link's frame.
SpatialTransform CheckJoint(const urdf::Joint& joint, const std::string& source) {
  const std::string where = source + ": joint '" + joint.name + "'";
  if (joint.type == urdf::Joint::FLOATING || joint.type == urdf::Joint::PLANAR) {
    throw UrdfError(where + " is " + JointTypeName(joint.type) +
                    ": floating-base and planar joints are not supported yet (only revolute, continuous, "
                    "prismatic and fixed)");
  }
  if (joint.type == urdf::Joint::UNKNOWN) throw UrdfError(where + " has an unknown type");
  if (joint.mimic) {
    throw UrdfError(where + " has <mimic> (mimicking '" + joint.mimic->joint_name +
                    "'): mimic joints are not supported");
  }
  SpatialTransform X;
  X.R_AB = RotationOf(joint.parent_to_joint_origin_transform.rotation);
  X.p_AB = VectorOf(joint.parent_to_joint_origin_transform.position);
  if (!X.R_AB.allFinite() || !X.p_AB.allFinite()) throw UrdfError(where + ": <origin> is not finite");
  if (joint.type != urdf::Joint::FIXED) {
    const Vector3 axis = VectorOf(joint.axis);
    if (!axis.allFinite()) throw UrdfError(where + ": <axis> is not finite");
    if (!(axis.norm() > 0.0)) throw UrdfError(where + ": <axis> is the zero vector");
  }
  return X;
}

UrdfLinkInertial ConvertInertial(const urdf::Link& link, const std::string& source) {
  UrdfLinkInertial out;
  out.link = link.name;
  if (!link.inertial) return out;
  out.present = true;
  const urdf::Inertial& in = *link.inertial;
  Matrix3 I_C;
  I_C << in.ixx, in.ixy, in.ixz,  //
      in.ixy, in.iyy, in.iyz,     //
      in.ixz, in.iyz, in.izz;
  const Matrix3 R_LC = RotationOf(in.origin.rotation);
  const Vector3 p_LC = VectorOf(in.origin.position);
  if (!std::isfinite(in.mass) || !I_C.allFinite() || !R_LC.allFinite() || !p_LC.allFinite()) {
    throw UrdfError(source + ": link '" + link.name + "': <inertial> has a non-finite number");
  }
  out.pi = InertialParams::FromMassComInertia(in.mass, p_LC, R_LC * I_C * R_LC.transpose());
  return out;
}

bool IsZero(const InertialParams& pi) { return (pi.vector().array() == 0.0).all(); }

// Each mesh file read once per URDF: its EnclosingSubset in the file's units, by resolved path.
using MeshCache = std::map<std::string, std::vector<Vector3>>;

// Points on one collision shape (primitive or mesh) posed at `origin` in its link's frame
// (body_region.hpp). A mesh is read when its file is found (mesh_vertices.hpp); otherwise *unread
// names it and no point is returned.
std::vector<Vector3> ShapePoints(const urdf::Geometry& geometry, const urdf::Pose& origin,
                                 const std::string& mesh_directory, MeshCache* cache, std::vector<std::string>* unread) {
  const Matrix3 R = RotationOf(origin.rotation);
  const Vector3 p = VectorOf(origin.position);
  switch (geometry.type) {
    case urdf::Geometry::SPHERE: return ShapePointsOfSphere(p, static_cast<const urdf::Sphere&>(geometry).radius);
    case urdf::Geometry::BOX: return ShapePointsOfBox(R, p, VectorOf(static_cast<const urdf::Box&>(geometry).dim));
    case urdf::Geometry::CYLINDER: {
      const auto& cylinder = static_cast<const urdf::Cylinder&>(geometry);
      return ShapePointsOfCylinder(R, p, cylinder.radius, cylinder.length);
    }
    case urdf::Geometry::MESH: {
      const auto& mesh = static_cast<const urdf::Mesh&>(geometry);
      if (mesh_directory.empty()) {
        unread->push_back(mesh.filename + " (URDF text without a folder: meshes not looked for)");
        return {};
      }
      // A scale is a unit conversion (1e-3 for millimetres) or a mirror: 1e-6 to 1e3 in size.
      const Vector3 scale = VectorOf(mesh.scale);
      if (!scale.allFinite() || scale.cwiseAbs().minCoeff() < 1e-6 || scale.cwiseAbs().maxCoeff() > 1e3) {
        unread->push_back(mesh.filename + " (scale " + FormatNumber(scale.x(), 6) + " " + FormatNumber(scale.y(), 6) + " " +
                          FormatNumber(scale.z(), 6) + " is not a size between 1e-6 and 1e3)");
        return {};
      }
      const std::optional<std::string> path = ResolveMeshUri(mesh.filename, mesh_directory);
      if (!path) {
        unread->push_back(mesh.filename + " (not found)");
        return {};
      }
      auto cached = cache->find(*path);
      if (cached == cache->end()) {
        try {
          cached = cache->emplace(*path, EnclosingSubset(ReadMeshVertices(*path))).first;
        } catch (const MeshError& e) {
          cached = cache->emplace(*path, std::vector<Vector3>{}).first;  // refused once, named each time
          unread->push_back(e.what());
          return {};
        }
      }
      if (cached->second.empty()) {
        unread->push_back(mesh.filename + " (" + *path + " could not be read)");
        return {};
      }
      std::vector<Vector3> points = cached->second;
      for (Vector3& x : points) x = R * scale.cwiseProduct(x) + p;
      return points;
    }
  }
  return {};
}

// Points on the collision shapes of `link` in its own frame (body_region.hpp); meshes that cannot be
// read are named in *unread. Visual shapes are not used: they are drawn for looks (a thin cylinder
// for an arm's link), not to enclose its material as collision shapes are.
std::vector<Vector3> LinkShapePoints(const urdf::Link& link, const std::string& mesh_directory, MeshCache* cache,
                                     std::vector<std::string>* unread) {
  std::vector<Vector3> points;
  for (const urdf::CollisionSharedPtr& c : link.collision_array) {
    if (!c || !c->geometry) continue;
    for (const Vector3& x : ShapePoints(*c->geometry, c->origin, mesh_directory, cache, unread)) {
      if (x.allFinite()) points.push_back(x);
    }
  }
  return points;
}

// Every tree body's collision points in its own frame (the links merged into it included). A body
// some of whose material is not drawn (a mesh not read, or a link with mass and no collision shape)
// gets none: part of a drawing would bound only part of the body (body_region.hpp, source 2 instead).
void GatherShapes(const urdf::ModelInterfaceSharedPtr& urdf_model, const std::string& mesh_directory, RobotModel* model) {
  model->body_shape_points.assign(model->body_links.size(), {});
  model->body_shape_meshes.assign(model->body_links.size(), 0);
  std::vector<bool> undrawn(model->body_links.size(), false);
  MeshCache cache;
  for (const auto& [name, placement] : model->placements) {
    if (placement.body < 0) continue;
    const urdf::LinkConstSharedPtr link = urdf_model->getLink(name);
    if (!link) continue;
    std::vector<std::string> unread;
    const std::vector<Vector3> points = LinkShapePoints(*link, mesh_directory, &cache, &unread);
    for (const Vector3& x : points) {
      model->body_shape_points[placement.body].push_back(placement.X_body_link.R_AB * x + placement.X_body_link.p_AB);
    }
    model->body_shape_meshes[placement.body] += static_cast<int>(unread.size());
    for (const std::string& u : unread) model->unread_meshes.push_back(name + ": " + u);
    const bool has_mass = link->inertial && link->inertial->mass > 0.0;
    if (!unread.empty() || (has_mass && points.empty())) undrawn[placement.body] = true;
  }
  for (std::size_t b = 0; b < undrawn.size(); ++b) {
    if (undrawn[b]) model->body_shape_points[b].clear();
  }
}

// A body of the tree being assembled (the tree's inertias cannot change after AddBody).
struct PendingBody {
  std::string link;
  int parent = -1;
  JointModel joint;
  InertialParams inertia;
  bool has_inertial = false;  // some link of it has <inertial>
  bool has_mass = false;      // some link of it has a non-zero <inertial>
};

// A tree body for a moving joint: its child link, hanging from parent_body at X_body_joint.
PendingBody MovingBody(const urdf::Joint& joint, int parent_body, const SpatialTransform& X_body_joint) {
  PendingBody body;
  body.link = joint.child_link_name;
  body.parent = parent_body;
  body.joint.name = joint.name;
  body.joint.type = joint.type == urdf::Joint::PRISMATIC ? JointType::kPrismatic : JointType::kRevolute;
  body.joint.R_parent_joint = X_body_joint.R_AB;
  body.joint.p_parent_joint = X_body_joint.p_AB;
  body.joint.axis = VectorOf(joint.axis).normalized();
  return body;
}

// Places every link: the joints in file order, each once its parent link is placed (parents before
// children). A moving joint starts a body; a fixed one puts its child link on its parent's body.
std::vector<PendingBody> PlaceLinks(const urdf::ModelInterfaceSharedPtr& urdf_model, const std::vector<std::string>& joints,
                                    const std::string& src, RobotModel* model) {
  std::vector<PendingBody> bodies;
  model->placements[model->root_link] = LinkPlacement{};
  std::vector<std::string> remaining = joints;
  while (!remaining.empty()) {
    std::vector<std::string> later;
    for (const std::string& joint_name : remaining) {
      const urdf::JointConstSharedPtr joint = urdf_model->getJoint(joint_name);
      if (!joint) continue;
      const auto parent = model->placements.find(joint->parent_link_name);
      if (parent == model->placements.end()) {
        later.push_back(joint_name);
        continue;
      }
      const SpatialTransform X_parent_joint = CheckJoint(*joint, src);
      const LinkPlacement parent_placement = parent->second;
      const SpatialTransform X_body_joint = Compose(parent_placement.X_body_link, X_parent_joint);
      LinkPlacement child;
      if (joint->type == urdf::Joint::FIXED) {
        child.body = parent_placement.body;
        child.X_body_link = X_body_joint;
      } else {
        bodies.push_back(MovingBody(*joint, parent_placement.body, X_body_joint));
        child.body = static_cast<int>(bodies.size()) - 1;
      }
      model->placements[joint->child_link_name] = child;
    }
    if (later.size() == remaining.size()) {
      throw UrdfError(src + ": joint '" + later.front() + "' hangs from a link that is not connected to the root '" +
                      model->root_link + "'");
    }
    remaining = later;
  }
  return bodies;
}

// Merges each link's inertial into its body (checked for consistency first if the options ask).
void MergeInertials(const RobotModel& model, const UrdfLoadOptions& options, const std::string& src,
                    std::vector<PendingBody>* bodies) {
  for (const UrdfLinkInertial& li : model.links) {
    const auto placement = model.placements.find(li.link);
    if (placement == model.placements.end() || placement->second.body < 0 || !li.present) continue;
    PendingBody& body = (*bodies)[placement->second.body];
    body.has_inertial = true;
    if (IsZero(li.pi)) continue;
    if (options.require_consistent_inertials) {
      const ConsistencyReport report = CheckConsistency(li.pi);
      if (!report.fully_consistent()) {
        throw UrdfError(src + ": link '" + li.link + "': <inertial> is not physically consistent: " + report.reason);
      }
    }
    body.has_mass = true;
    const SpatialTransform& X = placement->second.X_body_link;
    body.inertia = body.inertia + li.pi.Transformed(X.R_AB, X.p_AB);
  }
}

// Adds the bodies to the model's tree, in order, with their links and joints (a massless body
// rejected first if the options ask for consistent inertials).
void AddBodies(const std::vector<PendingBody>& bodies, const UrdfLoadOptions& options, const std::string& src,
               RobotModel* model) {
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    const PendingBody& body = bodies[i];
    if (options.require_consistent_inertials && !body.has_mass) {
      throw UrdfError(src + ": link '" + body.link + "' (moved by joint '" + body.joint.name + "') " +
                      (body.has_inertial ? "has zero mass: its <inertial> and those of the links fixed to it are zero"
                                         : "has no <inertial>, nor has any link fixed to it"));
    }
    try {
      model->tree.AddBody(body.link, body.parent, body.joint, body.inertia);
    } catch (const std::invalid_argument& e) {
      throw UrdfError(src + ": " + e.what());
    }
    model->body_links.push_back(body.link);
    model->body_has_inertial.push_back(body.has_inertial);
    model->dof_names.push_back(body.joint.name);
  }
}

}  // namespace

int RobotModel::DofIndex(const std::string& joint) const {
  for (std::size_t k = 0; k < dof_names.size(); ++k) {
    if (dof_names[k] == joint) return static_cast<int>(k);
  }
  return -1;
}

int RobotModel::BodyIndex(const std::string& link) const {
  const auto it = placements.find(link);
  return it == placements.end() ? -1 : it->second.body;
}

std::vector<EffectSpec> RobotModel::DeclaredEffects() const {
  std::vector<EffectSpec> specs;
  for (std::size_t k = 0; k < effects.size(); ++k) {
    if (effect_declared[k]) specs.push_back(effects[k].spec);
  }
  return specs;
}

SpatialTransform RobotModel::LinkInBody(const std::string& link) const {
  const auto it = placements.find(link);
  if (it == placements.end()) {
    throw std::invalid_argument("robot '" + name + "' has no link '" + link + "'");
  }
  return it->second.X_body_link;
}

RobotModel ParseUrdf(const std::string& xml, const std::string& source_name, const UrdfLoadOptions& options) {
  const std::string& src = source_name;
  tinyxml2::XMLDocument doc;
  const tinyxml2::XMLElement& robot_element = ParseRobotXml(xml, src, &doc);
  const FileOrder order = ReadFileOrder(robot_element);
  const urdf::ModelInterfaceSharedPtr urdf_model = ParseWithUrdfdom(RobotElementText(robot_element), src);

  RobotModel model;
  model.name = urdf_model->getName();
  model.root_link = urdf_model->getRoot()->name;

  // Every link's own inertial, in file order.
  for (const std::string& link_name : order.links) {
    const urdf::LinkConstSharedPtr link = urdf_model->getLink(link_name);
    if (!link) continue;
    model.links.push_back(ConvertInertial(*link, src));
  }

  std::vector<PendingBody> bodies = PlaceLinks(urdf_model, order.joints, src, &model);
  MergeInertials(model, options, src, &bodies);
  AddBodies(bodies, options, src, &model);
  GatherShapes(urdf_model, options.mesh_directory, &model);

  model.effects = detail::ReadModelEffects(robot_element, src, model.dof_names, &model.effect_declared);
  model.recorded_priors = detail::ReadRecordedPriors(robot_element, src, model.body_links);
  model.dof_limits = detail::ReadJointLimits(robot_element, src, model.dof_names);
  return model;
}

RobotModel LoadUrdf(const std::string& path, const UrdfLoadOptions& options) {
  UrdfLoadOptions with_directory = options;
  if (with_directory.mesh_directory.empty()) {
    with_directory.mesh_directory = std::filesystem::path(path).parent_path().string();
    if (with_directory.mesh_directory.empty()) with_directory.mesh_directory = ".";
  }
  return ParseUrdf(ReadUrdfFile(path), path, with_directory);
}

std::string ReadUrdfFile(const std::string& path) {
  try {
    return ReadInputFile(path, "URDF", kMaxUrdfBytes);
  } catch (const InputFileError& e) {
    throw UrdfError(e.what());
  }
}

}  // namespace inertial
