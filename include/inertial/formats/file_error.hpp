/// @file file_error.hpp
/// One wording for every file that cannot be opened, read or written, in every layer and command:
/// "cannot read the LCM log 'run.lcm': No such file or directory". The reason is the C library's
/// (errno at the failure), so the user learns why, not only that.
#pragma once

#include <cerrno>
#include <string>

namespace inertial {

/// "cannot <verb> [the <what> ]'<path>': <strerror(error)>"; verb e.g. "read", "write", "create";
/// what e.g. "LCM log" (empty: none). An error of 0 gives "unknown reason".
std::string CannotText(const std::string& verb, const std::string& what, const std::string& path, int error = errno);

}  // namespace inertial
