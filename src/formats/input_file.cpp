#include "inertial/formats/input_file.hpp"

#include <algorithm>
#include <cerrno>
#include <filesystem>
#include <fstream>

#include "inertial/formats/file_error.hpp"

namespace inertial {
namespace {

std::string Binary(std::size_t bytes) {
  if (bytes % (1024 * 1024) == 0) return std::to_string(bytes / (1024 * 1024)) + " MiB";
  if (bytes % 1024 == 0) return std::to_string(bytes / 1024) + " KiB";
  return std::to_string(bytes) + " bytes";
}

}  // namespace

std::string TooLargeText(const std::string& source, const std::string& what, std::size_t size, std::size_t limit,
                         bool at_least) {
  return source + ": the " + what + " is " + (at_least ? "at least " : "") + std::to_string(size) +
         " bytes, over its limit of " + Binary(limit) + ": refused before parsing";
}

std::string ReadInputFile(const std::string& path, const std::string& what, std::size_t max_bytes) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) {
    throw InputFileError(InputFileError::Reason::kUnreadable, CannotText("read", what, path, EISDIR));
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputFileError(InputFileError::Reason::kUnreadable, CannotText("read", what, path));
  const std::uintmax_t size = std::filesystem::file_size(path, ec);
  if (!ec && size > max_bytes) {
    throw InputFileError(InputFileError::Reason::kTooLarge, TooLargeText(path, what, static_cast<std::size_t>(size), max_bytes));
  }
  std::string text;
  char chunk[1 << 16];
  // At most max_bytes + 1 bytes: the one over the limit tells a file that is too large.
  while (text.size() <= max_bytes) {
    const std::size_t want = std::min(sizeof chunk, max_bytes + 1 - text.size());
    if (in.read(chunk, static_cast<std::streamsize>(want)).gcount() <= 0) break;
    text.append(chunk, static_cast<std::size_t>(in.gcount()));
  }
  if (in.bad()) throw InputFileError(InputFileError::Reason::kUnreadable, CannotText("read", what, path));
  if (text.size() > max_bytes) {
    throw InputFileError(InputFileError::Reason::kTooLarge, TooLargeText(path, what, text.size(), max_bytes, true));
  }
  return text;
}

}  // namespace inertial
