#include "inertial/formats/sample_line_names.hpp"

#include <cstdlib>

namespace inertial {

void NameSamplesByLine(const std::string& file, const std::vector<int>& lines, std::vector<std::string>* messages) {
  NameSamplesByLine({file}, {0, static_cast<int>(lines.size())}, lines, messages);
}

void NameSamplesByLine(const std::vector<std::string>& files, const std::vector<int>& starts, const std::vector<int>& lines,
                       std::vector<std::string>* messages) {
  for (std::string& message : *messages) {
    const std::size_t at = message.find("sample ");
    if (at == std::string::npos) continue;
    const int i = std::atoi(message.c_str() + at + 7);
    if (i < 0 || i >= static_cast<int>(lines.size())) continue;
    for (std::size_t k = 0; k < files.size() && k + 1 < starts.size(); ++k) {
      if (i >= starts[k] && i < starts[k + 1]) message = files[k] + ":" + std::to_string(lines[i]) + ": " + message;
    }
  }
}

}  // namespace inertial
