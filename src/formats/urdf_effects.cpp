#include "urdf_effects.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <set>
#include <sstream>

#include "inertial/inertia/consistency.hpp"
#include "inertial/formats/number_parsing.hpp"
#include "inertial/model/rotation_from_rpy.hpp"
#include "inertial/formats/urdf_model.hpp"
#include "inertial/model/number_text.hpp"

namespace inertial::detail {
namespace {

std::string ElementText(const tinyxml2::XMLElement& e) {
  return "<" + std::string(e.Name()) + "> (line " + std::to_string(e.GetLineNum()) + ")";
}

// A required (or optional, with a default) finite decimal attribute.
double Attribute(const tinyxml2::XMLElement& e, const char* name, const std::string& source, const double* fallback = nullptr) {
  const char* text = e.Attribute(name);
  if (text == nullptr) {
    if (fallback != nullptr) return *fallback;
    throw UrdfError(source + ": " + ElementText(e) + " has no attribute '" + name + "'");
  }
  try {
    return ParseDouble(text, std::string(name));
  } catch (const InvalidNumber& err) {
    throw UrdfError(source + ": " + ElementText(e) + ": attribute " + err.what());
  }
}

std::vector<double> Numbers(const tinyxml2::XMLElement& e, const char* name, const std::string& source, std::size_t count,
                            const std::vector<double>& fallback) {
  const char* text = e.Attribute(name);
  if (text == nullptr) return fallback;
  std::vector<double> v;
  try {
    v = ParseNumberList(text, std::string(name));
  } catch (const InvalidNumber& err) {
    throw UrdfError(source + ": " + ElementText(e) + ": attribute " + err.what());
  }
  if (v.size() != count) {
    throw UrdfError(source + ": " + ElementText(e) + ": attribute '" + name + "' has " + std::to_string(v.size()) +
                    " numbers, " + std::to_string(count) + " expected");
  }
  return v;
}

std::string Name(EffectKind kind, const std::string& target) { return std::string(ToString(kind)) + "@" + target; }

void AddNote(tinyxml2::XMLDocument& doc, tinyxml2::XMLElement* element, const std::map<std::string, std::string>& notes,
             const std::string& name) {
  const auto it = notes.find(name);
  if (it != notes.end()) element->InsertFirstChild(doc.NewComment(CommentSafe(" " + it->second + " ").c_str()));
}

}  // namespace

std::string CommentSafe(std::string text) {
  for (std::size_t k = text.find("--"); k != std::string::npos; k = text.find("--", k)) text.replace(k, 2, "- -");
  if (!text.empty() && text.back() == '-') text += ' ';
  return text;
}

void FillInertialElement(tinyxml2::XMLDocument& doc, tinyxml2::XMLElement* inertial, const InertialParams& pi) {
  const double m = pi.mass();
  const Vector3 c = m != 0.0 ? pi.com() : Vector3::Zero();
  const Matrix3 I = m != 0.0 ? pi.rotational_inertia_about_com() : pi.rotational_inertia_about_origin();
  tinyxml2::XMLElement* origin = doc.NewElement("origin");
  origin->SetAttribute("xyz", (FormatNumber(c.x(), kRoundTripDigits) + " " + FormatNumber(c.y(), kRoundTripDigits) + " " + FormatNumber(c.z(), kRoundTripDigits)).c_str());
  origin->SetAttribute("rpy", "0 0 0");
  inertial->InsertEndChild(origin);
  tinyxml2::XMLElement* mass = doc.NewElement("mass");
  mass->SetAttribute("value", FormatNumber(m, kRoundTripDigits).c_str());
  inertial->InsertEndChild(mass);
  tinyxml2::XMLElement* inertia = doc.NewElement("inertia");
  inertia->SetAttribute("ixx", FormatNumber(I(0, 0), kRoundTripDigits).c_str());
  inertia->SetAttribute("ixy", FormatNumber(I(0, 1), kRoundTripDigits).c_str());
  inertia->SetAttribute("ixz", FormatNumber(I(0, 2), kRoundTripDigits).c_str());
  inertia->SetAttribute("iyy", FormatNumber(I(1, 1), kRoundTripDigits).c_str());
  inertia->SetAttribute("iyz", FormatNumber(I(1, 2), kRoundTripDigits).c_str());
  inertia->SetAttribute("izz", FormatNumber(I(2, 2), kRoundTripDigits).c_str());
  inertial->InsertEndChild(inertia);
}

InertialParams ReadInertialElement(const tinyxml2::XMLElement& inertial, const std::string& where) {
  const tinyxml2::XMLElement* mass = inertial.FirstChildElement("mass");
  const tinyxml2::XMLElement* inertia = inertial.FirstChildElement("inertia");
  if (mass == nullptr || inertia == nullptr) {
    throw UrdfError(where + ": <inertial> needs <mass> and <inertia>");
  }
  Vector3 xyz = Vector3::Zero(), rpy = Vector3::Zero();
  if (const tinyxml2::XMLElement* origin = inertial.FirstChildElement("origin")) {
    const std::vector<double> p = Numbers(*origin, "xyz", where, 3, {0, 0, 0});
    const std::vector<double> r = Numbers(*origin, "rpy", where, 3, {0, 0, 0});
    xyz = Vector3(p[0], p[1], p[2]);
    rpy = Vector3(r[0], r[1], r[2]);
  }
  const double m = Attribute(*mass, "value", where);
  Matrix3 I_C;
  const double ixx = Attribute(*inertia, "ixx", where), iyy = Attribute(*inertia, "iyy", where);
  const double izz = Attribute(*inertia, "izz", where), ixy = Attribute(*inertia, "ixy", where);
  const double iyz = Attribute(*inertia, "iyz", where), ixz = Attribute(*inertia, "ixz", where);
  I_C << ixx, ixy, ixz, ixy, iyy, iyz, ixz, iyz, izz;
  const Matrix3 R = RotationFromRpy(rpy);
  const InertialParams pi = InertialParams::FromMassComInertia(m, xyz, R * I_C * R.transpose());
  const ConsistencyReport report = CheckConsistency(pi);
  if (!report.fully_consistent()) {
    throw UrdfError(where + ": <inertial> is not physically consistent: " + report.reason);
  }
  return pi;
}

namespace {

using JointDynamicsMap = std::map<std::string, std::pair<double, double>>;  // joint -> (damping, friction)

// The standard <dynamics> of the moving joints.
JointDynamicsMap ReadJointDynamics(const tinyxml2::XMLElement& robot, const std::string& source,
                                   const std::set<std::string>& moving) {
  JointDynamicsMap dynamics;
  for (const tinyxml2::XMLElement* j = robot.FirstChildElement("joint"); j; j = j->NextSiblingElement("joint")) {
    const char* name = j->Attribute("name");
    const tinyxml2::XMLElement* d = j->FirstChildElement("dynamics");
    if (name == nullptr || d == nullptr || moving.count(name) == 0) continue;
    const std::string where = source + ": joint '" + std::string(name) + "'";
    const double zero = 0.0;
    const double damping = Attribute(*d, "damping", where, &zero), friction = Attribute(*d, "friction", where, &zero);
    if (damping < 0 || friction < 0) {
      throw UrdfError(where + ": <dynamics> damping and friction must be >= 0 (got " + FormatNumber(damping, kRoundTripDigits) + ", " +
                      FormatNumber(friction, kRoundTripDigits) + ")");
    }
    dynamics[name] = {damping, friction};
  }
  return dynamics;
}

// The extension element (at most one, version 1), or null.
const tinyxml2::XMLElement* EffectsElement(const tinyxml2::XMLElement& robot, const std::string& source) {
  const tinyxml2::XMLElement* ext = robot.FirstChildElement(kEffectsElement);
  if (ext != nullptr && ext->NextSiblingElement(kEffectsElement) != nullptr) {
    throw UrdfError(source + ": more than one <" + std::string(kEffectsElement) + "> element");
  }
  if (ext != nullptr) {
    const char* version = ext->Attribute("version");
    if (version == nullptr || std::string(version) != "1") {
      throw UrdfError(source + ": <" + std::string(kEffectsElement) + "> (line " + std::to_string(ext->GetLineNum()) +
                      ") has version " + (version ? "'" + std::string(version) + "'" : std::string("(none)")) +
                      "; this reader knows version 1");
    }
  }
  return ext;
}

// One child of the extension element: its kind, attributes and children checked, its target a
// moving joint (or a link, for a payload), not stated before (`names`); values not read yet.
ModelEffect ReadEffectElement(const tinyxml2::XMLElement& element, const std::string& source,
                              const std::set<std::string>& moving, std::set<std::string>& names, std::string* where_out) {
  const tinyxml2::XMLElement* e = &element;
  const std::string tag = e->Name();
  ModelEffect m;
  bool known = false;
  for (EffectKind k : AllEffectKinds()) {
    if (tag == ToString(k)) {
      m.spec.kind = k;
      known = true;
    }
  }
  const std::string where = source + ": <" + std::string(kEffectsElement) + ">: " + ElementText(*e);
  if (!known) {
    throw UrdfError(where +
                    " is not an effect (viscous, coulomb, asymmetric, sigmoid, offset, armature, spring, rotor, payload, gain)");
  }
  // Nothing unknown is silently ignored: every attribute and child must be the kind's own.
  static const std::map<EffectKind, std::set<std::string>> kAttributes = {
      {EffectKind::kViscous, {"joint"}},
      {EffectKind::kCoulomb, {"joint", "velocity_scale"}},
      {EffectKind::kAsymmetric, {"joint", "velocity_scale", "positive", "negative"}},
      {EffectKind::kSigmoid, {"joint", "amplitude", "steepness", "shift"}},
      {EffectKind::kOffset, {"joint", "torque"}},
      {EffectKind::kArmature, {"joint", "inertia"}},
      {EffectKind::kSpring, {"joint", "stiffness", "rest_position"}},
      {EffectKind::kRotor, {"joint", "gear_ratio"}},
      {EffectKind::kPayload, {"link"}},
      {EffectKind::kGain, {"joint", "value"}}};
  for (const tinyxml2::XMLAttribute* a = e->FirstAttribute(); a != nullptr; a = a->Next()) {
    if (kAttributes.at(m.spec.kind).count(a->Name()) == 0) {
      throw UrdfError(where + " has an unknown attribute '" + std::string(a->Name()) + "'");
    }
  }
  const bool body_effect = m.spec.kind == EffectKind::kRotor || m.spec.kind == EffectKind::kPayload;
  int children = 0;
  for (const tinyxml2::XMLElement* c = e->FirstChildElement(); c != nullptr; c = c->NextSiblingElement()) {
    if (!body_effect || std::string(c->Name()) != "inertial" || ++children > 1) {
      throw UrdfError(where + " has an unexpected child <" + std::string(c->Name()) + ">" +
                      (body_effect ? " (one <inertial> only)" : " (it takes attributes only)"));
    }
  }
  for (const tinyxml2::XMLNode* n = e->FirstChild(); n != nullptr; n = n->NextSibling()) {
    if (n->ToText() != nullptr) throw UrdfError(where + " holds text; it takes attributes only");
  }
  const char* target = e->Attribute(m.spec.kind == EffectKind::kPayload ? "link" : "joint");
  if (target == nullptr || *target == '\0') {
    throw UrdfError(where + " has no attribute '" + (m.spec.kind == EffectKind::kPayload ? "link" : "joint") + "'");
  }
  m.spec.target = target;
  m.spec.text = Name(m.spec.kind, m.spec.target) + " (" + source + ")";
  if (m.spec.kind != EffectKind::kPayload && moving.count(m.spec.target) == 0) {
    throw UrdfError(where + ": '" + m.spec.target + "' is not a moving joint of the robot");
  }
  if (!names.insert(Name(m.spec.kind, m.spec.target)).second) {
    throw UrdfError(where + ": " + Name(m.spec.kind, m.spec.target) + " is stated twice");
  }
  *where_out = where;
  return m;
}

// The values of effect m from its element (viscous and Coulomb from the joint's <dynamics>).
void ReadEffectValues(const tinyxml2::XMLElement& element, const std::string& where, const JointDynamicsMap& dynamics,
                      ModelEffect& m) {
  const tinyxml2::XMLElement* e = &element;
  auto non_negative = [&](const char* attribute) {
    const double v = Attribute(*e, attribute, where);
    if (v < 0) throw UrdfError(where + ": attribute '" + attribute + "' must be >= 0, got " + FormatNumber(v, kRoundTripDigits));
    return v;
  };
  const auto dyn = dynamics.find(m.spec.target);
  switch (m.spec.kind) {
    case EffectKind::kViscous:
    case EffectKind::kCoulomb:
      if (dyn == dynamics.end()) {
        throw UrdfError(where + ": joint '" + m.spec.target + "' has no <dynamics> element holding the coefficient");
      }
      if (m.spec.kind == EffectKind::kCoulomb) {
        m.spec.velocity_scale = Attribute(*e, "velocity_scale", where);
        if (!(m.spec.velocity_scale > 0)) throw UrdfError(where + ": attribute 'velocity_scale' must be > 0");
      }
      m.values = {m.spec.kind == EffectKind::kViscous ? dyn->second.first : dyn->second.second};
      break;
    case EffectKind::kAsymmetric:
      m.spec.velocity_scale = Attribute(*e, "velocity_scale", where);
      if (!(m.spec.velocity_scale > 0)) throw UrdfError(where + ": attribute 'velocity_scale' must be > 0");
      m.values = {non_negative("positive"), non_negative("negative")};
      break;
    case EffectKind::kSigmoid:
      m.spec.steepness = Attribute(*e, "steepness", where);
      if (!(m.spec.steepness > 0)) throw UrdfError(where + ": attribute 'steepness' must be > 0");
      m.spec.shift = Attribute(*e, "shift", where);
      m.values = {non_negative("amplitude")};
      break;
    case EffectKind::kOffset: m.values = {Attribute(*e, "torque", where)}; break;
    case EffectKind::kArmature: m.values = {non_negative("inertia")}; break;
    case EffectKind::kSpring: m.values = {non_negative("stiffness"), Attribute(*e, "rest_position", where)}; break;
    case EffectKind::kGain:
      m.values = {Attribute(*e, "value", where)};
      if (!(m.values[0] > 0)) throw UrdfError(where + ": attribute 'value' (the log's unit per N m) must be > 0");
      break;
    case EffectKind::kRotor:
    case EffectKind::kPayload: {
      if (m.spec.kind == EffectKind::kRotor) {
        m.spec.gear_ratio = Attribute(*e, "gear_ratio", where);
        if (m.spec.gear_ratio == 0.0) throw UrdfError(where + ": attribute 'gear_ratio' must be non-zero");
      }
      const tinyxml2::XMLElement* inertial = e->FirstChildElement("inertial");
      if (inertial == nullptr) throw UrdfError(where + " has no <inertial>");
      m.spec.inertia = ReadInertialElement(*inertial, where);
      break;
    }
  }
}

// Viscous and Coulomb terms first, in joint order (stated, or from <dynamics> alone), then the rest
// as listed; `declared` says which were stated in the extension element.
std::vector<ModelEffect> OrderModelEffects(const std::vector<ModelEffect>& listed, const JointDynamicsMap& dynamics,
                                           const std::string& source, const std::vector<std::string>& moving_joints,
                                           std::vector<bool>* declared) {
  std::vector<ModelEffect> effects;
  declared->clear();
  for (const std::string& joint : moving_joints) {
    const auto dyn = dynamics.find(joint);
    for (EffectKind kind : {EffectKind::kViscous, EffectKind::kCoulomb}) {
      const auto it = std::find_if(listed.begin(), listed.end(), [&](const ModelEffect& m) {
        return m.spec.kind == kind && m.spec.target == joint;
      });
      const double value = dyn == dynamics.end() ? 0.0 : (kind == EffectKind::kViscous ? dyn->second.first : dyn->second.second);
      if (it != listed.end()) {
        effects.push_back(*it);
        declared->push_back(true);
      } else if (value > 0) {
        ModelEffect m;
        m.spec.kind = kind;
        m.spec.target = joint;
        m.spec.text = Name(kind, joint) + " (<dynamics> of " + source + ")";
        m.values = {value};
        effects.push_back(m);
        declared->push_back(false);
      }
    }
  }
  for (const ModelEffect& m : listed) {
    if (m.spec.kind == EffectKind::kViscous || m.spec.kind == EffectKind::kCoulomb) continue;
    effects.push_back(m);
    declared->push_back(true);
  }
  return effects;
}

// One of our extension elements of `robot` (<inertial_effects>, <inertial_priors>), about to be
// written: every earlier `name` removed, then, unless there is nothing to write (`empty`), a new
// one (version 1, opening with `comment`) returned for the caller to fill and insert.
tinyxml2::XMLElement* FreshExtension(tinyxml2::XMLDocument& doc, tinyxml2::XMLElement* robot, const char* name,
                                     bool empty, const char* comment) {
  while (tinyxml2::XMLElement* old = robot->FirstChildElement(name)) robot->DeleteChild(old);
  if (empty) return nullptr;
  tinyxml2::XMLElement* element = doc.NewElement(name);
  element->SetAttribute("version", 1);
  element->InsertEndChild(doc.NewComment(comment));
  return element;
}

}  // namespace

std::vector<ModelEffect> ReadModelEffects(const tinyxml2::XMLElement& robot, const std::string& source,
                                          const std::vector<std::string>& moving_joints, std::vector<bool>* declared) {
  const std::set<std::string> moving(moving_joints.begin(), moving_joints.end());
  const JointDynamicsMap dynamics = ReadJointDynamics(robot, source, moving);
  const tinyxml2::XMLElement* ext = EffectsElement(robot, source);
  std::vector<ModelEffect> listed;
  std::set<std::string> names;
  for (const tinyxml2::XMLElement* e = ext ? ext->FirstChildElement() : nullptr; e; e = e->NextSiblingElement()) {
    std::string where;
    ModelEffect m = ReadEffectElement(*e, source, moving, names, &where);
    ReadEffectValues(*e, where, dynamics, m);
    listed.push_back(m);
  }
  return OrderModelEffects(listed, dynamics, source, moving_joints, declared);
}

void WriteModelEffects(tinyxml2::XMLDocument& doc, tinyxml2::XMLElement* robot, const std::vector<ModelEffect>& effects,
                       const std::map<std::string, std::string>& notes, const std::string& path) {
  std::map<std::string, tinyxml2::XMLElement*> joints;
  for (tinyxml2::XMLElement* j = robot->FirstChildElement("joint"); j; j = j->NextSiblingElement("joint")) {
    if (const char* name = j->Attribute("name")) joints.emplace(name, j);
  }
  std::map<std::string, std::pair<double, double>> dynamics;  // joint -> (damping, friction)
  for (const ModelEffect& m : effects) {
    for (double v : m.values) {
      if (!std::isfinite(v)) throw UrdfError(path + ": " + Name(m.spec.kind, m.spec.target) + ": a coefficient is not finite");
    }
    if (m.spec.kind != EffectKind::kPayload && joints.count(m.spec.target) == 0) {
      throw UrdfError(path + ": no joint named '" + m.spec.target + "' (" + Name(m.spec.kind, m.spec.target) + ")");
    }
    if (m.spec.kind == EffectKind::kViscous) dynamics[m.spec.target].first = m.values.at(0);
    if (m.spec.kind == EffectKind::kCoulomb) dynamics[m.spec.target].second = m.values.at(0);
  }
  // <dynamics> of every moving joint agrees with the model: the model's coefficients, or zero where
  // the file had a value the model does not have (a reader would otherwise add it back).
  for (const auto& [name, joint] : joints) {
    const char* type = joint->Attribute("type");
    if (type != nullptr && std::strcmp(type, "fixed") == 0) continue;
    tinyxml2::XMLElement* element = joint->FirstChildElement("dynamics");
    const auto it = dynamics.find(name);
    if (it == dynamics.end() && element == nullptr) continue;
    if (element == nullptr) {
      element = doc.NewElement("dynamics");
      joint->InsertEndChild(element);
    }
    const std::pair<double, double> v = it == dynamics.end() ? std::pair<double, double>(0.0, 0.0) : it->second;
    element->SetAttribute("damping", FormatNumber(v.first, kRoundTripDigits).c_str());
    element->SetAttribute("friction", FormatNumber(v.second, kRoundTripDigits).c_str());
  }
  tinyxml2::XMLElement* ext = FreshExtension(
      doc, robot, kEffectsElement, effects.empty(),
      " inertial's model effects (README: the model file). Viscous and Coulomb coefficients are the joints' "
      "<dynamics damping friction>; other URDF readers ignore this element. ");
  if (ext == nullptr) return;
  for (const ModelEffect& m : effects) {
    tinyxml2::XMLElement* e = doc.NewElement(std::string(ToString(m.spec.kind)).c_str());
    e->SetAttribute(m.spec.kind == EffectKind::kPayload ? "link" : "joint", m.spec.target.c_str());
    switch (m.spec.kind) {
      case EffectKind::kViscous: break;
      case EffectKind::kCoulomb: e->SetAttribute("velocity_scale", FormatNumber(m.spec.velocity_scale, kRoundTripDigits).c_str()); break;
      case EffectKind::kAsymmetric:
        e->SetAttribute("velocity_scale", FormatNumber(m.spec.velocity_scale, kRoundTripDigits).c_str());
        e->SetAttribute("positive", FormatNumber(m.values.at(0), kRoundTripDigits).c_str());
        e->SetAttribute("negative", FormatNumber(m.values.at(1), kRoundTripDigits).c_str());
        break;
      case EffectKind::kSigmoid:
        e->SetAttribute("amplitude", FormatNumber(m.values.at(0), kRoundTripDigits).c_str());
        e->SetAttribute("steepness", FormatNumber(m.spec.steepness, kRoundTripDigits).c_str());
        e->SetAttribute("shift", FormatNumber(m.spec.shift, kRoundTripDigits).c_str());
        break;
      case EffectKind::kOffset: e->SetAttribute("torque", FormatNumber(m.values.at(0), kRoundTripDigits).c_str()); break;
      case EffectKind::kArmature: e->SetAttribute("inertia", FormatNumber(m.values.at(0), kRoundTripDigits).c_str()); break;
      case EffectKind::kSpring:
        e->SetAttribute("stiffness", FormatNumber(m.values.at(0), kRoundTripDigits).c_str());
        e->SetAttribute("rest_position", FormatNumber(m.values.at(1), kRoundTripDigits).c_str());
        break;
      case EffectKind::kGain: e->SetAttribute("value", FormatNumber(m.values.at(0), kRoundTripDigits).c_str()); break;
      case EffectKind::kRotor:
      case EffectKind::kPayload: {
        if (m.spec.kind == EffectKind::kRotor) e->SetAttribute("gear_ratio", FormatNumber(m.spec.gear_ratio, kRoundTripDigits).c_str());
        if (!m.spec.inertia || !m.spec.inertia->AllFinite()) {
          throw UrdfError(path + ": " + Name(m.spec.kind, m.spec.target) + ": no finite inertia to write");
        }
        tinyxml2::XMLElement* inertial = doc.NewElement("inertial");
        FillInertialElement(doc, inertial, *m.spec.inertia);
        e->InsertEndChild(inertial);
        break;
      }
    }
    AddNote(doc, e, notes, Name(m.spec.kind, m.spec.target));
    ext->InsertEndChild(e);
  }
  robot->InsertEndChild(ext);
}

std::map<std::string, InertialParams> ReadRecordedPriors(const tinyxml2::XMLElement& robot, const std::string& source,
                                                         const std::vector<std::string>& body_links) {
  std::map<std::string, InertialParams> priors;
  const tinyxml2::XMLElement* element = robot.FirstChildElement(kPriorsElement);
  if (element == nullptr) return priors;
  const std::string where = source + ": <" + std::string(kPriorsElement) + "> (line " +
                            std::to_string(element->GetLineNum()) + ")";
  if (element->NextSiblingElement(kPriorsElement) != nullptr) throw UrdfError(where + " is given twice");
  const char* version = element->Attribute("version");
  if (version == nullptr || std::string(version) != "1") {
    throw UrdfError(where + " has version " + (version ? "'" + std::string(version) + "'" : std::string("(none)")) +
                    "; this reader knows version 1");
  }
  const std::set<std::string> links(body_links.begin(), body_links.end());
  for (const tinyxml2::XMLElement* e = element->FirstChildElement(); e != nullptr; e = e->NextSiblingElement()) {
    const std::string at = source + ": <" + std::string(kPriorsElement) + ">: " + ElementText(*e);
    if (std::string(e->Name()) != "prior") throw UrdfError(at + " is not a <prior>");
    for (const tinyxml2::XMLAttribute* a = e->FirstAttribute(); a != nullptr; a = a->Next()) {
      if (std::string(a->Name()) != "link") throw UrdfError(at + " has an unknown attribute '" + std::string(a->Name()) + "'");
    }
    const char* link = e->Attribute("link");
    if (link == nullptr || *link == '\0') throw UrdfError(at + " has no attribute 'link'");
    if (links.count(link) == 0) throw UrdfError(at + ": '" + std::string(link) + "' is not a link that moves with a joint");
    const tinyxml2::XMLElement* inertial = e->FirstChildElement("inertial");
    if (inertial == nullptr || inertial->NextSiblingElement() != nullptr || e->FirstChildElement() != inertial) {
      throw UrdfError(at + " must hold exactly one <inertial>");
    }
    if (!priors.emplace(link, ReadInertialElement(*inertial, at)).second) {
      throw UrdfError(at + ": link '" + std::string(link) + "' is given twice");
    }
  }
  return priors;
}

void WriteRecordedPriors(tinyxml2::XMLDocument& doc, tinyxml2::XMLElement* robot,
                         const std::map<std::string, InertialParams>& priors, const std::string& path) {
  tinyxml2::XMLElement* element = FreshExtension(
      doc, robot, kPriorsElement, priors.empty(),
      " inertial: each link's inertia in the URDF the values were identified from (the fit's prior), in the "
      "link's frame. `inertial validate` and `inertial check` judge the links' plausibility against it (the mass "
      "ratio, the region built from it); other URDF readers ignore this element. ");
  if (element == nullptr) return;
  for (const auto& [link, pi] : priors) {
    if (!pi.AllFinite()) throw UrdfError(path + ": the prior of link '" + link + "' is not finite");
    tinyxml2::XMLElement* e = doc.NewElement("prior");
    e->SetAttribute("link", link.c_str());
    tinyxml2::XMLElement* inertial = doc.NewElement("inertial");
    FillInertialElement(doc, inertial, pi);
    e->InsertEndChild(inertial);
    element->InsertEndChild(e);
  }
  robot->InsertEndChild(element);
}

}  // namespace inertial::detail
