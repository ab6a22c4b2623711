/// @file progress.hpp
/// Progress of a long run on stderr, only when stderr is a terminal (never in a pipe, a log file
/// or a test): one line rewritten in place ("\r"), at most five times a second, erased at the end
/// so the command's own output is unchanged. Thread-safe (fits may report from worker threads).
#pragma once

#include <chrono>
#include <cstdio>
#include <mutex>
#include <string>

#include <unistd.h>

namespace inertial::cli {

class Progress {
 public:
  explicit Progress(std::string label) : label_(std::move(label)), enabled_(::isatty(STDERR_FILENO) == 1) {}
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;
  ~Progress() { Done(); }

  /// Erases the line (before the command prints its results); later Show calls show again.
  void Done() {
    std::lock_guard<std::mutex> lock(mutex_);
    if (shown_) std::fprintf(stderr, "\r%*s\r", static_cast<int>(width_), "");
    std::fflush(stderr);
    shown_ = false;
    width_ = 0;
  }

  /// "label: text", if a fifth of a second has passed since the last line.
  void Show(const std::string& text) {
    if (!enabled_) return;
    std::lock_guard<std::mutex> lock(mutex_);
    const auto now = std::chrono::steady_clock::now();
    if (shown_ && now - last_ < std::chrono::milliseconds(200)) return;
    last_ = now;
    const std::string line = label_ + ": " + text;
    std::fprintf(stderr, "\r%s%*s", line.c_str(), static_cast<int>(width_ > line.size() ? width_ - line.size() : 0), "");
    std::fflush(stderr);
    width_ = std::max(width_, line.size());
    shown_ = true;
  }
  /// "label: 42 %".
  void Fraction(double f) { Show(std::to_string(static_cast<int>(100.0 * f)) + " %"); }

 private:
  std::string label_;
  bool enabled_;
  bool shown_ = false;
  std::size_t width_ = 0;
  std::chrono::steady_clock::time_point last_;
  std::mutex mutex_;
};

}  // namespace inertial::cli
