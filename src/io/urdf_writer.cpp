#include "inertial/io/urdf_writer.hpp"

#include <tinyxml2.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

#include "xml_error.hpp"

namespace inertial {
namespace {

constexpr const char* kNotePrefix = " Written by inertial";

std::string Number(double value) {
  char buffer[40];
  std::snprintf(buffer, sizeof(buffer), "%.17g", value);
  return buffer;
}

std::string Triple(const Vector3& v) { return Number(v.x()) + " " + Number(v.y()) + " " + Number(v.z()); }

std::string Join(const std::vector<std::string>& items) {
  std::string out;
  for (std::size_t k = 0; k < items.size(); ++k) out += (k ? ", " : "") + items[k];
  return out;
}

// XML comments may not contain "--".
std::string CommentSafe(std::string text) {
  for (std::size_t k = text.find("--"); k != std::string::npos; k = text.find("--", k)) text.replace(k, 2, "- -");
  return text;
}

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

void FillInertial(tinyxml2::XMLDocument& doc, tinyxml2::XMLElement* inertial, const InertialParams& pi) {
  const double m = pi.mass();
  const Vector3 c = m != 0.0 ? pi.com() : Vector3::Zero();
  const Matrix3 I = m != 0.0 ? pi.rotational_inertia_about_com() : pi.rotational_inertia_about_origin();
  tinyxml2::XMLElement* origin = doc.NewElement("origin");
  origin->SetAttribute("xyz", Triple(c).c_str());
  origin->SetAttribute("rpy", "0 0 0");
  inertial->InsertEndChild(origin);
  tinyxml2::XMLElement* mass = doc.NewElement("mass");
  mass->SetAttribute("value", Number(m).c_str());
  inertial->InsertEndChild(mass);
  tinyxml2::XMLElement* inertia = doc.NewElement("inertia");
  inertia->SetAttribute("ixx", Number(I(0, 0)).c_str());
  inertia->SetAttribute("ixy", Number(I(0, 1)).c_str());
  inertia->SetAttribute("ixz", Number(I(0, 2)).c_str());
  inertia->SetAttribute("iyy", Number(I(1, 1)).c_str());
  inertia->SetAttribute("iyz", Number(I(1, 2)).c_str());
  inertia->SetAttribute("izz", Number(I(2, 2)).c_str());
  inertial->InsertEndChild(inertia);
}

std::string ChangeSummary(const std::map<std::string, InertialParams>& new_inertias,
                          const std::set<std::string>& removed_inertials,
                          const std::map<std::string, JointDynamics>& dynamics, const std::string& in_path) {
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
  if (parts.empty()) parts.push_back("nothing changed");
  std::string summary = kNotePrefix + (" from " + in_path + ": ");
  for (std::size_t k = 0; k < parts.size(); ++k) summary += (k ? "; " : "") + parts[k];
  return CommentSafe(summary + ". Everything else is as in the original. ");
}

}  // namespace

void WriteUrdfWithInertias(const std::string& in_path, const std::string& out_path,
                           const std::map<std::string, InertialParams>& new_inertias,
                           const std::set<std::string>& removed_inertials,
                           const std::map<std::string, JointDynamics>& dynamics) {
  std::error_code ec;
  if (std::filesystem::is_directory(in_path, ec)) throw UrdfError(in_path + ": cannot read the file: it is a directory");
  std::ifstream in(in_path, std::ios::binary);
  if (!in) throw UrdfError(in_path + ": cannot open the file (" + std::strerror(errno) + ")");
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw UrdfError(in_path + ": cannot read the file");
  const std::string xml = text.str();

  tinyxml2::XMLDocument doc;
  if (doc.Parse(xml.c_str(), xml.size()) != tinyxml2::XML_SUCCESS) {
    throw UrdfError(in_path + ": is not a valid URDF: " + detail::DescribeXmlError(doc));
  }
  tinyxml2::XMLElement* robot = doc.RootElement();
  if (robot == nullptr || std::strcmp(robot->Name(), "robot") != 0) {
    throw UrdfError(in_path + ": is not a valid URDF: the root element is not <robot>");
  }

  const std::map<std::string, tinyxml2::XMLElement*> links = ChildrenByName(robot, "link");
  const std::map<std::string, tinyxml2::XMLElement*> joints = ChildrenByName(robot, "joint");
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
    FillInertial(doc, inertial, pi);
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
    element->SetAttribute("damping", Number(d.damping).c_str());
    element->SetAttribute("friction", Number(d.friction).c_str());
  }

  // One note of ours at the top: an earlier one (the file was written by inertial before) is replaced.
  for (tinyxml2::XMLNode* node = doc.FirstChild(); node != nullptr;) {
    tinyxml2::XMLNode* next = node->NextSibling();
    if (node->ToComment() != nullptr && std::strncmp(node->Value(), kNotePrefix, std::strlen(kNotePrefix)) == 0) {
      doc.DeleteChild(node);
    }
    node = next;
  }
  tinyxml2::XMLComment* comment = doc.NewComment(ChangeSummary(new_inertias, removed_inertials, dynamics, in_path).c_str());
  tinyxml2::XMLNode* first = doc.FirstChild();
  if (first != nullptr && first->ToDeclaration() != nullptr) {
    doc.InsertAfterChild(first, comment);
  } else {
    doc.InsertFirstChild(comment);
  }

  tinyxml2::XMLPrinter printer;
  doc.Print(&printer);
  std::ofstream out(out_path, std::ios::binary | std::ios::trunc);
  if (!out) throw UrdfError(out_path + ": cannot open the file for writing (" + std::strerror(errno) + ")");
  out.write(printer.CStr(), static_cast<std::streamsize>(printer.CStrSize() - 1));
  out.close();
  if (!out) throw UrdfError(out_path + ": cannot write the file");
}

}  // namespace inertial
