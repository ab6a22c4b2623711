#include "inertial/formats/sample_line_names.hpp"

#include <cstdlib>

namespace inertial {

void NameSamplesByLine(const std::string& file, const std::vector<int>& lines, std::vector<std::string>* messages) {
  for (std::string& message : *messages) {
    const std::size_t at = message.find("sample ");
    if (at == std::string::npos) continue;
    const int i = std::atoi(message.c_str() + at + 7);
    if (i >= 0 && i < static_cast<int>(lines.size())) message = file + ":" + std::to_string(lines[i]) + ": " + message;
  }
}

}  // namespace inertial
