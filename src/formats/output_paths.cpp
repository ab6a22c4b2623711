#include "inertial/formats/output_paths.hpp"

#include <filesystem>
#include <system_error>

namespace inertial {

bool SameFile(const std::string& a, const std::string& b) {
  if (a.empty() || b.empty()) return false;
  std::error_code ec;
  if (std::filesystem::exists(a, ec) && std::filesystem::exists(b, ec)) return std::filesystem::equivalent(a, b, ec);
  return std::filesystem::weakly_canonical(a, ec) == std::filesystem::weakly_canonical(b, ec);
}

std::optional<std::string> OutputPathClash(const std::vector<PathOption>& outputs,
                                           const std::vector<PathOption>& inputs) {
  for (std::size_t i = 0; i < outputs.size(); ++i) {
    const PathOption& out = outputs[i];
    for (const PathOption& in : inputs) {
      if (SameFile(out.path, in.path)) {
        return out.option + " '" + out.path + "' is the " + in.option +
               " input: refusing to overwrite an input (choose another output path)";
      }
    }
    for (std::size_t k = i + 1; k < outputs.size(); ++k) {
      if (SameFile(out.path, outputs[k].path)) {
        return out.option + " and " + outputs[k].option + " name the same file '" + out.path + "'";
      }
    }
  }
  return std::nullopt;
}

}  // namespace inertial
