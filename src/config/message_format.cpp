#include "inertial/config/message_format.hpp"

#include <map>
#include <stdexcept>
#include <string>

#include "inertial/formats/json_integer.hpp"

namespace inertial {

LcmLayout ParseLcmLayout(const nlohmann::json& j) {
  if (!j.is_object() || !j.contains("fields") || !j["fields"].is_array()) {
    throw std::invalid_argument("LCM layout: expected an object with a \"fields\" array");
  }
  LcmLayout layout;
  if (j.contains("type")) {
    if (!j["type"].is_string()) throw std::invalid_argument("LCM layout: \"type\" must be a string");
    layout.type_name = j["type"].get<std::string>();
  }
  static const std::map<std::string, LcmType> kTypes{
      {"int8_t", LcmType::kInt8},   {"int16_t", LcmType::kInt16}, {"int32_t", LcmType::kInt32},
      {"int64_t", LcmType::kInt64}, {"byte", LcmType::kByte},     {"float", LcmType::kFloat},
      {"double", LcmType::kDouble}, {"string", LcmType::kString}, {"boolean", LcmType::kBoolean}};
  int index = 0;
  for (const nlohmann::json& e : j["fields"]) {
    const std::string where = "LCM layout: field " + std::to_string(index++);
    if (!e.is_object() || !e.contains("name") || !e["name"].is_string() || !e.contains("type") ||
        !e["type"].is_string()) {
      throw std::invalid_argument(where + ": expected {\"name\": ..., \"type\": ...}");
    }
    LcmField f;
    f.name = e["name"].get<std::string>();
    const auto t = kTypes.find(e["type"].get<std::string>());
    if (t == kTypes.end()) {
      throw std::invalid_argument(where + " '" + f.name + "': unknown type '" + e["type"].get<std::string>() +
                                  "' (nested structs are not supported)");
    }
    f.type = t->second;
    if (e.contains("length")) {
      if (const std::optional<std::int64_t> n = JsonInteger(e["length"], 0, 4096)) {
        f.length = static_cast<int>(*n);
      } else if (e["length"].is_string()) {
        f.length_field = e["length"].get<std::string>();
      } else {
        throw std::invalid_argument(where + " '" + f.name + "': length must be an integer in [0, 4096] or a field name");
      }
    }
    layout.fields.push_back(f);
  }
  CheckLcmLayout(layout);
  return layout;
}

JointMessageFormat ParseJointMessageFormat(const nlohmann::json& j) {
  if (!j.is_object()) throw std::invalid_argument("message format: expected a JSON object");
  JointMessageFormat f;
  auto text_or_null = [&](const char* key, std::string* out) {
    if (!j.contains(key)) return;
    if (j[key].is_null()) {
      out->clear();
    } else if (j[key].is_string()) {
      *out = j[key].get<std::string>();
    } else {
      throw std::invalid_argument(std::string("message format: \"") + key + "\" must be a field name or null");
    }
  };
  if (j.contains("layout")) f.layout = ParseLcmLayout(j["layout"]);
  text_or_null("utime", &f.utime_field);
  text_or_null("names", &f.names_field);
  if (j.contains("joint_names")) {
    if (!j["joint_names"].is_array()) throw std::invalid_argument("message format: \"joint_names\" must be a list");
    for (const nlohmann::json& name : j["joint_names"]) {
      if (!name.is_string()) throw std::invalid_argument("message format: \"joint_names\" must be a list of strings");
      f.joint_names.push_back(name.get<std::string>());
    }
    if (!j.contains("names")) f.names_field.clear();
  }
  text_or_null("q", &f.q);
  text_or_null("qd", &f.qd);
  text_or_null("qdd", &f.qdd);
  text_or_null("tau", &f.tau);
  if (j.contains("accel_cutoff_hz")) {
    if (!j["accel_cutoff_hz"].is_number() || !(j["accel_cutoff_hz"].get<double>() > 0)) {
      throw std::invalid_argument("message format: \"accel_cutoff_hz\" must be a positive number");
    }
    f.accel_cutoff_hz = j["accel_cutoff_hz"].get<double>();
  }
  return f;
}

}  // namespace inertial
