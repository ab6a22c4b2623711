/// @file cli_support.hpp
/// Running the built `inertial` CLI (INERTIAL_CLI) as a subprocess in end-to-end tests: no shell,
/// stdin from a string, stdout and stderr through temporary files (no pipe deadlocks).
#pragma once

#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include <atomic>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <sstream>
#include <vector>

namespace inertial::testing {

namespace fs = std::filesystem;

struct CliRun {
  int exit_code = -1;  ///< the exit status, or 128 + signal number if killed by a signal
  std::string out;
  std::string err;
};

inline std::string ReadFile(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

inline fs::path UniqueTempPath(const std::string& stem) {
  static std::atomic<int> counter{0};
  return fs::temp_directory_path() /
         ("inertial_cli_test_" + std::to_string(getpid()) + "_" + std::to_string(counter++) + "_" + stem);
}

// Writes `text` to a new UniqueTempPath(stem) and returns its path.
inline std::string WriteUniqueTempFile(const std::string& stem, const std::string& text) {
  const std::string path = UniqueTempPath(stem).string();
  std::ofstream(path) << text;
  return path;
}

// Runs the program at path argv0 (no shell, no PATH search) with `args`, feeding `input` on stdin;
// stdout and stderr go to temporary files (no pipe deadlocks), read back after the process ends.
inline CliRun RunProgram(const std::string& argv0, const std::vector<std::string>& args, const std::string& input = "") {
  CliRun run;
  const fs::path in_path = UniqueTempPath("stdin"), out_path = UniqueTempPath("stdout"),
                 err_path = UniqueTempPath("stderr");
  { std::ofstream(in_path, std::ios::binary) << input; }
  std::vector<std::string> storage;
  storage.push_back(argv0);
  storage.insert(storage.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& s : storage) argv.push_back(s.data());
  argv.push_back(nullptr);

  const pid_t pid = fork();
  if (pid < 0) {
    ADD_FAILURE() << "fork failed: " << std::strerror(errno);
    return run;
  }
  if (pid == 0) {
    const int in = open(in_path.c_str(), O_RDONLY);
    const int out = open(out_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
    const int err = open(err_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
    if (in < 0 || out < 0 || err < 0) _exit(126);
    if (dup2(in, 0) < 0 || dup2(out, 1) < 0 || dup2(err, 2) < 0) _exit(126);
    execv(argv[0], argv.data());
    _exit(127);
  }
  int status = 0;
  while (waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) {
      ADD_FAILURE() << "waitpid failed: " << std::strerror(errno);
      break;
    }
  }
  if (WIFEXITED(status)) run.exit_code = WEXITSTATUS(status);
  else if (WIFSIGNALED(status)) run.exit_code = 128 + WTERMSIG(status);
  run.out = ReadFile(out_path);
  run.err = ReadFile(err_path);
  std::error_code ec;
  fs::remove(in_path, ec);
  fs::remove(out_path, ec);
  fs::remove(err_path, ec);
  return run;
}

// Runs INERTIAL_CLI with `args`, as RunProgram.
inline CliRun RunCli(const std::vector<std::string>& args, const std::string& input = "") {
  const char* cli = std::getenv("INERTIAL_CLI");
  if (cli == nullptr) {
    ADD_FAILURE() << "INERTIAL_CLI is not set";
    return CliRun{};
  }
  return RunProgram(cli, args, input);
}

inline std::string Describe(const CliRun& r) {
  return "exit " + std::to_string(r.exit_code) + "\n--- stdout ---\n" + r.out + "--- stderr ---\n" + r.err;
}

// The held-out error as a user reads it: `validate --model model --data data --json`'s relative RMS
// torque error over every joint.
inline double HeldOutError(const std::string& model, const std::string& data) {
  const CliRun r = RunCli({"validate", "--model", model, "--data", data, "--json"});
  EXPECT_EQ(r.exit_code, 0) << Describe(r);
  return nlohmann::json::parse(r.out).at("relative_rms").at("total").get<double>();
}

// A fitting command (identify, replay ...) run with `--effects effects` (none if empty) and
// `--write-urdf out`; returns out.
inline std::string FitToUrdf(std::vector<std::string> command, const std::string& effects, const std::string& out) {
  if (!effects.empty()) command.insert(command.end(), {"--effects", effects});
  command.insert(command.end(), {"--write-urdf", out});
  const CliRun r = RunCli(command);
  EXPECT_EQ(r.exit_code, 0) << Describe(r);
  return out;
}

// The CSV log at `from` without its qdd_ columns (comment lines kept).
inline void DropAccelerations(const std::string& from, const std::string& to) {
  std::ifstream in(from);
  std::ofstream out(to);
  std::string line;
  std::vector<bool> keep;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') {
      out << line << "\n";
      continue;
    }
    std::vector<std::string> cells;
    std::stringstream ss(line);
    for (std::string cell; std::getline(ss, cell, ',');) cells.push_back(cell);
    if (keep.empty()) {
      for (const std::string& c : cells) keep.push_back(c.rfind("qdd_", 0) != 0);
    }
    std::string joined;
    for (std::size_t i = 0; i < cells.size() && i < keep.size(); ++i) {
      if (!keep[i]) continue;
      joined += (joined.empty() ? "" : ",") + cells[i];
    }
    out << joined << "\n";
  }
}

// The real KUKA LWR4+ measurements (../shared/data/kuka_lwr4 beside the source tree: its URDF and
// measurements_{1,2}.csv), or "" where they are absent (the caller skips, saying so).
inline std::string SharedKukaData() {
  const char* source = std::getenv("INERTIAL_SOURCE_DIR");
  const std::string data = std::string(source != nullptr ? source : ".") + "/../shared/data/kuka_lwr4";
  return fs::exists(data + "/measurements_1.csv") && fs::exists(data + "/kuka_lwr4.urdf") ? data : "";
}

inline bool Contains(const std::string& haystack, const std::string& needle) {
  return haystack.find(needle) != std::string::npos;
}

}  // namespace inertial::testing
