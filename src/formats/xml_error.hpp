/// @file xml_error.hpp
/// (Private to the io layer.) A short description of a tinyxml2 parse or load error.
#pragma once

#include <tinyxml2.h>

#include <string>

namespace inertial::detail {

/// e.g. "XML error at line 3: XML_ERROR_MISMATCHED_ELEMENT (XMLElement name=link)", "the document
/// is empty".
inline std::string DescribeXmlError(const tinyxml2::XMLDocument& doc) {
  if (doc.ErrorID() == tinyxml2::XML_ERROR_EMPTY_DOCUMENT) return "the document is empty";
  std::string text = std::string("XML error at line ") + std::to_string(doc.ErrorLineNum()) + ": " + doc.ErrorName();
  // ErrorStr() is "Error=... ErrorID=... Line number=N[: detail]": keep only the detail.
  const std::string full = doc.ErrorStr() != nullptr ? doc.ErrorStr() : "";
  const std::size_t line_at = full.find("Line number=");
  const std::size_t detail_at = line_at == std::string::npos ? std::string::npos : full.find(": ", line_at);
  if (detail_at != std::string::npos) text += " (" + full.substr(detail_at + 2) + ")";
  return text;
}

}  // namespace inertial::detail
