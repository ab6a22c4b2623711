#include "inertial/formats/urdf_writer.hpp"
#include "inertial/formats/file_error.hpp"
#include "inertial/formats/mesh_vertices.hpp"
#include "inertial/model/number_text.hpp"

#include <sys/stat.h>
#include <tinyxml2.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <vector>

#include "urdf_effects.hpp"
#include "xml_error.hpp"

namespace inertial {
namespace {

constexpr const char* kNotePrefix = " Written by inertial";

std::string Join(const std::vector<std::string>& items) {
  std::string out;
  for (std::size_t k = 0; k < items.size(); ++k) out += (k ? ", " : "") + items[k];
  return out;
}

using detail::CommentSafe;

std::map<std::string, tinyxml2::XMLElement*> ChildrenByName(tinyxml2::XMLElement* robot, const char* tag) {
  std::map<std::string, tinyxml2::XMLElement*> out;
  for (tinyxml2::XMLElement* e = robot->FirstChildElement(tag); e; e = e->NextSiblingElement(tag)) {
    if (const char* name = e->Attribute("name")) out.emplace(name, e);
  }
  return out;
}

template <typename Keys>
void RequireKnown(const Keys& keys, const std::map<std::string, tinyxml2::XMLElement*>& known, const std::string& path,
                  const std::string& what) {
  std::vector<std::string> unknown;
  for (const auto& key : keys) {
    if (known.count(key) == 0) unknown.push_back("'" + key + "'");
  }
  if (!unknown.empty()) throw UrdfError(path + ": no " + what + " named " + Join(unknown));
}

std::vector<std::string> Keys(const std::map<std::string, InertialParams>& m) {
  std::vector<std::string> keys;
  for (const auto& kv : m) keys.push_back(kv.first);
  return keys;
}

std::string ChangeSummary(const UrdfModelChanges& changes, const std::map<std::string, JointDynamics>& dynamics,
                          const std::string& in_path) {
  const std::map<std::string, InertialParams>& new_inertias = changes.inertias;
  const std::set<std::string>& removed_inertials = changes.removed_inertials;
  std::vector<std::string> parts;
  if (!new_inertias.empty()) parts.push_back("new <inertial> for links " + Join(Keys(new_inertias)));
  if (!removed_inertials.empty()) {
    parts.push_back("<inertial> removed from links " +
                    Join(std::vector<std::string>(removed_inertials.begin(), removed_inertials.end())));
  }
  if (!dynamics.empty()) {
    std::vector<std::string> joints;
    for (const auto& kv : dynamics) joints.push_back(kv.first);
    parts.push_back("<dynamics> set for joints " + Join(joints));
  }
  if (changes.effects) {
    std::vector<std::string> names;
    for (const ModelEffect& m : *changes.effects) names.push_back(std::string(ToString(m.spec.kind)) + "@" + m.spec.target);
    parts.push_back(names.empty() ? "no effects (<dynamics> zeroed)"
                                  : "effects " + Join(names) + " (<dynamics> and <inertial_effects>)");
  }
  if (parts.empty()) parts.push_back("nothing changed");
  std::string summary = kNotePrefix + (" from " + in_path + (changes.origin.empty() ? "" : ", " + changes.origin) + ": ");
  for (std::size_t k = 0; k < parts.size(); ++k) summary += (k ? "; " : "") + parts[k];
  return CommentSafe(summary + ". Everything else is as in the original. ");
}

}  // namespace

namespace {

using ElementsByName = std::map<std::string, tinyxml2::XMLElement*>;

// The URDF text parsed into doc; its <robot> element. UrdfError naming in_path otherwise.
tinyxml2::XMLElement* ParseRobot(const std::string& xml, const std::string& in_path, tinyxml2::XMLDocument& doc) {
  if (doc.Parse(xml.c_str(), xml.size()) != tinyxml2::XML_SUCCESS) {
    throw UrdfError(in_path + ": is not a valid URDF: " + detail::DescribeXmlError(doc));
  }
  tinyxml2::XMLElement* robot = doc.RootElement();
  if (robot == nullptr || std::strcmp(robot->Name(), "robot") != 0) {
    throw UrdfError(in_path + ": is not a valid URDF: the root element is not <robot>");
  }
  return robot;
}

// Every change names a link or joint of the file, no link is both given an inertia and stripped of
// it, and every new value is finite.
void CheckChanges(const UrdfModelChanges& changes, const std::map<std::string, JointDynamics>& dynamics,
                  const ElementsByName& links, const ElementsByName& joints, const std::string& in_path) {
  const std::map<std::string, InertialParams>& new_inertias = changes.inertias;
  const std::set<std::string>& removed_inertials = changes.removed_inertials;
  RequireKnown(Keys(new_inertias), links, in_path, "link");
  RequireKnown(removed_inertials, links, in_path, "link");
  std::vector<std::string> dynamics_joints;
  for (const auto& kv : dynamics) dynamics_joints.push_back(kv.first);
  RequireKnown(dynamics_joints, joints, in_path, "joint");
  for (const auto& [link, pi] : new_inertias) {
    if (removed_inertials.count(link) != 0) {
      throw UrdfError(in_path + ": link '" + link + "' is both given a new <inertial> and listed for removal");
    }
    if (!pi.AllFinite()) throw UrdfError(in_path + ": link '" + link + "': the new inertia is not finite");
  }
  for (const auto& [joint, d] : dynamics) {
    if (!std::isfinite(d.damping) || !std::isfinite(d.friction)) {
      throw UrdfError(in_path + ": joint '" + joint + "': damping or friction is not finite");
    }
  }

}

// The new <inertial>s (with their notes), the removed ones and the joints' <dynamics>, in doc.
void ApplyChanges(const UrdfModelChanges& changes, const std::map<std::string, JointDynamics>& dynamics,
                  const ElementsByName& links, const ElementsByName& joints, tinyxml2::XMLDocument& doc) {
  const std::map<std::string, InertialParams>& new_inertias = changes.inertias;
  const std::set<std::string>& removed_inertials = changes.removed_inertials;
  for (const auto& [link_name, pi] : new_inertias) {
    tinyxml2::XMLElement* link = links.at(link_name);
    tinyxml2::XMLElement* inertial = link->FirstChildElement("inertial");
    if (inertial != nullptr) {
      inertial->DeleteChildren();
      // Attributes are not part of URDF's <inertial>; drop any so the element is exactly the new one.
      while (const tinyxml2::XMLAttribute* a = inertial->FirstAttribute()) inertial->DeleteAttribute(a->Name());
    } else {
      inertial = doc.NewElement("inertial");
      link->InsertFirstChild(inertial);
    }
    detail::FillInertialElement(doc, inertial, pi);
    const auto note = changes.notes.find(link_name);
    if (note != changes.notes.end()) inertial->InsertFirstChild(doc.NewComment(CommentSafe(" " + note->second + " ").c_str()));
  }
  for (const std::string& link_name : removed_inertials) {
    tinyxml2::XMLElement* link = links.at(link_name);
    while (tinyxml2::XMLElement* inertial = link->FirstChildElement("inertial")) link->DeleteChild(inertial);
  }
  for (const auto& [joint_name, d] : dynamics) {
    tinyxml2::XMLElement* joint = joints.at(joint_name);
    tinyxml2::XMLElement* element = joint->FirstChildElement("dynamics");
    if (element == nullptr) {
      element = doc.NewElement("dynamics");
      joint->InsertEndChild(element);
    }
    element->SetAttribute("damping", FormatNumber(d.damping, kRoundTripDigits).c_str());
    element->SetAttribute("friction", FormatNumber(d.friction, kRoundTripDigits).c_str());
  }

}

// Meshes the input names relative to its folder (a path, or `package://` found above it) that the
// written file's folder would not find: named by their absolute path (file://), so that the
// written model's links keep the regions their meshes drew (body_region.hpp). Other meshes, and
// those not found from the input either, are left as they are.
void KeepMeshesFound(tinyxml2::XMLElement* robot, const std::string& in_path, const std::string& out_path) {
  namespace fs = std::filesystem;
  const std::string in_dir = fs::path(in_path).parent_path().empty() ? "." : fs::path(in_path).parent_path().string();
  const std::string out_dir = fs::path(out_path).parent_path().empty() ? "." : fs::path(out_path).parent_path().string();
  std::vector<tinyxml2::XMLElement*> stack{robot};
  while (!stack.empty()) {
    tinyxml2::XMLElement* e = stack.back();
    stack.pop_back();
    for (tinyxml2::XMLElement* c = e->FirstChildElement(); c != nullptr; c = c->NextSiblingElement()) stack.push_back(c);
    if (std::strcmp(e->Name(), "mesh") != 0 || e->Attribute("filename") == nullptr) continue;
    const std::string uri = e->Attribute("filename");
    const std::optional<std::string> from_in = ResolveMeshUri(uri, in_dir);
    if (!from_in) continue;
    const std::optional<std::string> from_out = ResolveMeshUri(uri, out_dir);
    std::error_code ec;
    if (from_out && fs::equivalent(*from_in, *from_out, ec)) continue;
    e->SetAttribute("filename", ("file://" + fs::absolute(*from_in, ec).lexically_normal().string()).c_str());
  }
}

// One note of ours at the top of doc: an earlier one (the file was written by inertial before) is
// replaced.
void ReplaceNote(tinyxml2::XMLDocument& doc, const std::string& note) {
  for (tinyxml2::XMLNode* node = doc.FirstChild(); node != nullptr;) {
    tinyxml2::XMLNode* next = node->NextSibling();
    if (node->ToComment() != nullptr && std::strncmp(node->Value(), kNotePrefix, std::strlen(kNotePrefix)) == 0) {
      doc.DeleteChild(node);
    }
    node = next;
  }
  tinyxml2::XMLComment* comment = doc.NewComment(note.c_str());
  tinyxml2::XMLNode* first = doc.FirstChild();
  if (first != nullptr && first->ToDeclaration() != nullptr) {
    doc.InsertAfterChild(first, comment);
  } else {
    doc.InsertFirstChild(comment);
  }

}

// The text written to out_path through a temporary file beside it (a unique name, created
// exclusively: never an existing file or a link planted there), renamed over it: never half a
// file, even on a signal.
void WriteAtomically(const std::string& out_path, const tinyxml2::XMLPrinter& printer) {
  std::error_code status_error;
  const std::filesystem::file_status target = std::filesystem::status(out_path, status_error);
  if (std::filesystem::exists(target) && !std::filesystem::is_regular_file(target)) {
    throw UrdfError(out_path + ": is not a regular file (a directory, device or pipe): refusing to replace it");
  }
  std::string temporary = out_path + ".XXXXXX";
  const int fd = mkstemp(temporary.data());
  if (fd < 0) throw UrdfError(CannotText("write", "", out_path));
  const char* bytes = printer.CStr();
  std::size_t left = static_cast<std::size_t>(printer.CStrSize() - 1);
  bool ok = true;
  while (left > 0 && ok) {
    const ssize_t n = write(fd, bytes, left);
    if (n < 0 && errno == EINTR) continue;
    ok = n > 0;
    if (ok) {
      bytes += n;
      left -= static_cast<std::size_t>(n);
    }
  }
  ok = (fchmod(fd, 0644) == 0) && ok;
  ok = (close(fd) == 0) && ok;
  if (!ok) {
    std::remove(temporary.c_str());
    throw UrdfError(out_path + ": cannot write the file");
  }
  std::error_code rename_error;
  std::filesystem::rename(temporary, out_path, rename_error);
  if (rename_error) {
    std::remove(temporary.c_str());
    throw UrdfError(out_path + ": cannot write the file (" + rename_error.message() + ")");
  }
}

void WriteChanges(const std::string& in_path, const std::string& out_path, const UrdfModelChanges& changes,
                  const std::map<std::string, JointDynamics>& dynamics) {
  const std::string xml = ReadUrdfFile(in_path);
  tinyxml2::XMLDocument doc;
  tinyxml2::XMLElement* robot = ParseRobot(xml, in_path, doc);
  const ElementsByName links = ChildrenByName(robot, "link");
  const ElementsByName joints = ChildrenByName(robot, "joint");
  CheckChanges(changes, dynamics, links, joints, in_path);
  ApplyChanges(changes, dynamics, links, joints, doc);
  if (changes.effects) detail::WriteModelEffects(doc, robot, *changes.effects, changes.notes, in_path);
  if (changes.priors) {
    RequireKnown(Keys(*changes.priors), links, in_path, "link");
    detail::WriteRecordedPriors(doc, robot, *changes.priors, in_path);
  }
  KeepMeshesFound(robot, in_path, out_path);
  ReplaceNote(doc, ChangeSummary(changes, dynamics, in_path));
  tinyxml2::XMLPrinter printer;
  doc.Print(&printer);
  WriteAtomically(out_path, printer);
}

}  // namespace

void WriteUrdfModel(const std::string& in_path, const std::string& out_path, const UrdfModelChanges& changes) {
  WriteChanges(in_path, out_path, changes, {});
}

void WriteUrdfWithInertias(const std::string& in_path, const std::string& out_path,
                           const std::map<std::string, InertialParams>& new_inertias,
                           const std::set<std::string>& removed_inertials,
                           const std::map<std::string, JointDynamics>& dynamics) {
  UrdfModelChanges changes;
  changes.inertias = new_inertias;
  changes.removed_inertials = removed_inertials;
  WriteChanges(in_path, out_path, changes, dynamics);
}

}  // namespace inertial
