/// @file can_bus.hpp
/// A CAN bus: set the identifiers to receive, read with a timeout, write. Two implementations:
/// SocketCAN (Linux PF_CAN raw socket: kernel filters on the configured identifiers, non-blocking
/// reads with poll, classic and FD frames, error frames received and counted) and an in-memory bus
/// for tests and simulation.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <deque>
#include <mutex>
#include <string>
#include <vector>

#include "inertial/transport/can_frame.hpp"

namespace inertial {

struct CanId {
  std::uint32_t id = 0;
  bool extended = false;
};

class CanBus {
 public:
  virtual ~CanBus() = default;
  /// Receive only these identifiers (and error frames); empty: everything.
  virtual void SetFilters(const std::vector<CanId>& ids) = 0;
  /// Waits up to timeout_ms for a frame: true with *frame set (t = reception time [s]), false on
  /// timeout. @throws std::runtime_error if the bus failed.
  virtual bool Read(CanFrame* frame, int timeout_ms) = 0;
  /// @throws std::runtime_error if the frame cannot be sent.
  virtual void Write(const CanFrame& frame) = 0;
  virtual std::uint64_t error_frames() const = 0;
};

/// Frames pushed by another thread (Push) are read in order, filtered as SocketCAN would.
class InMemoryCanBus : public CanBus {
 public:
  void SetFilters(const std::vector<CanId>& ids) override;
  bool Read(CanFrame* frame, int timeout_ms) override;
  void Write(const CanFrame& frame) override;
  std::uint64_t error_frames() const override;
  void Push(const CanFrame& frame);
  std::vector<CanFrame> written() const;

 private:
  bool Passes(const CanFrame& f) const;
  mutable std::mutex mutex_;
  std::condition_variable ready_;
  std::deque<CanFrame> frames_;
  std::vector<CanId> filters_;
  std::vector<CanFrame> written_;
  std::uint64_t errors_ = 0;
};

/// Whether this kernel offers PF_CAN raw sockets; *why says why not.
bool SocketCanAvailable(std::string* why);

class SocketCanBus : public CanBus {
 public:
  /// Opens a raw CAN socket on `interface` (e.g. can0, vcan0) with CAN FD frames enabled.
  /// @throws std::runtime_error naming the interface and the system error.
  explicit SocketCanBus(const std::string& interface);
  ~SocketCanBus() override;
  SocketCanBus(const SocketCanBus&) = delete;
  SocketCanBus& operator=(const SocketCanBus&) = delete;
  void SetFilters(const std::vector<CanId>& ids) override;
  bool Read(CanFrame* frame, int timeout_ms) override;
  void Write(const CanFrame& frame) override;
  std::uint64_t error_frames() const override { return errors_; }

 private:
  std::string interface_;
  int fd_ = -1;
  std::uint64_t errors_ = 0;
};

}  // namespace inertial
