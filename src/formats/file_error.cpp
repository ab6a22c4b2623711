#include "inertial/formats/file_error.hpp"

#include <cstring>

namespace inertial {

std::string CannotText(const std::string& verb, const std::string& what, const std::string& path, int error) {
  return "cannot " + verb + " " + (what.empty() ? "" : "the " + what + " ") + "'" + path +
         "': " + (error == 0 ? "unknown reason" : std::strerror(error));
}

}  // namespace inertial
