#include "inertial/report/gnuplot.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace inertial {

void RunGnuplot(const std::filesystem::path& dir, const std::string& script) {
  const pid_t pid = fork();
  if (pid < 0) throw std::runtime_error(std::string("fork() for gnuplot failed: ") + std::strerror(errno));
  if (pid == 0) {
    if (chdir(dir.c_str()) != 0) _exit(126);
    execlp("gnuplot", "gnuplot", script.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  int status = 0;
  if (waitpid(pid, &status, 0) < 0) throw std::runtime_error(std::string("waitpid() for gnuplot failed: ") + std::strerror(errno));
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    const int code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    throw std::runtime_error("gnuplot " + script + " in '" + dir.string() + "' failed (exit status " +
                             std::to_string(code) + (code == 127 ? ": gnuplot not found on PATH" : "") + ")");
  }
}

std::string GnuplotQuoted(const std::string& text) {
  std::string out = "'";
  for (char c : text) {
    if (c == '\'') out += "''";
    else if (c != '\n') out += c;
  }
  return out + "'";
}

}  // namespace inertial
