/// @file urdf_text.hpp
/// Test helpers: URDF text built from numbers (written with %.17g, so nothing is lost), and
/// temporary file paths.
#pragma once

#include <unistd.h>

#include <atomic>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include <functional>

#include <gtest/gtest.h>

#include "inertial/inertia/types.hpp"
#include "inertial/formats/urdf_model.hpp"
#include "inertial/model/number_text.hpp"

namespace inertial::testing {

inline std::string Num(double value) { return FormatNumber(value, kRoundTripDigits); }

inline std::string Triple(const Vector3& v) { return Num(v.x()) + " " + Num(v.y()) + " " + Num(v.z()); }

/// <inertial> with the COM frame at xyz/rpy and the tensor about the COM in that frame's axes.
inline std::string InertialXml(double mass, const Vector3& xyz, const Vector3& rpy, const Matrix3& I) {
  return "<inertial><origin xyz=\"" + Triple(xyz) + "\" rpy=\"" + Triple(rpy) + "\"/><mass value=\"" + Num(mass) +
         "\"/><inertia ixx=\"" + Num(I(0, 0)) + "\" ixy=\"" + Num(I(0, 1)) + "\" ixz=\"" + Num(I(0, 2)) +
         "\" iyy=\"" + Num(I(1, 1)) + "\" iyz=\"" + Num(I(1, 2)) + "\" izz=\"" + Num(I(2, 2)) + "\"/></inertial>";
}

inline std::string LinkXml(const std::string& name, const std::string& inside = "") {
  return "<link name=\"" + name + "\">" + inside + "</link>\n";
}

/// A joint of URDF type `type` ("revolute", "continuous", "prismatic", "fixed", ...); revolute and
/// prismatic joints get a <limit>. `extra` is appended inside the element.
inline std::string JointXml(const std::string& name, const std::string& type, const std::string& parent,
                            const std::string& child, const Vector3& xyz = Vector3::Zero(),
                            const Vector3& rpy = Vector3::Zero(), const Vector3& axis = Vector3::UnitZ(),
                            const std::string& extra = "") {
  std::string s = "<joint name=\"" + name + "\" type=\"" + type + "\"><parent link=\"" + parent +
                  "\"/><child link=\"" + child + "\"/><origin xyz=\"" + Triple(xyz) + "\" rpy=\"" + Triple(rpy) +
                  "\"/>";
  if (type != "fixed") s += "<axis xyz=\"" + Triple(axis) + "\"/>";
  if (type == "revolute" || type == "prismatic") {
    s += "<limit lower=\"-3\" upper=\"3\" effort=\"100\" velocity=\"10\"/>";
  }
  return s + extra + "</joint>\n";
}

inline std::string RobotXml(const std::string& name, const std::string& body) {
  return "<?xml version=\"1.0\"?>\n<robot name=\"" + name + "\">\n" + body + "</robot>\n";
}

inline std::filesystem::path TempUrdfPath(const std::string& stem) {
  static std::atomic<int> counter{0};
  return std::filesystem::temp_directory_path() /
         ("inertial_urdf_test_" + std::to_string(getpid()) + "_" + std::to_string(counter++) + "_" + stem);
}

inline void WriteTextFile(const std::filesystem::path& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

inline std::string ReadTextFile(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

/// The UrdfError message of f(), or a test failure if it does not throw one.
inline std::string ErrorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const UrdfError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no UrdfError thrown";
  return "";
}

}  // namespace inertial::testing
