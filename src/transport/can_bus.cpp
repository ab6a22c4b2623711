#include "inertial/transport/can_bus.hpp"

#include <fcntl.h>
#include <linux/can.h>
#include <linux/can/raw.h>
#include <net/if.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <stdexcept>

namespace inertial {
namespace {

double Now() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

std::string SystemError(const std::string& what) { return what + ": " + std::strerror(errno); }

}  // namespace

void InMemoryCanBus::SetFilters(const std::vector<CanId>& ids) {
  std::lock_guard<std::mutex> lock(mutex_);
  filters_ = ids;
}

bool InMemoryCanBus::Passes(const CanFrame& f) const {
  if (f.error || filters_.empty()) return true;
  return std::any_of(filters_.begin(), filters_.end(),
                     [&](const CanId& c) { return c.id == f.id && c.extended == f.extended; });
}

void InMemoryCanBus::Push(const CanFrame& frame) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!Passes(frame)) return;
    if (frame.error) ++errors_;
    frames_.push_back(frame);
  }
  ready_.notify_one();
}

bool InMemoryCanBus::Read(CanFrame* frame, int timeout_ms) {
  std::unique_lock<std::mutex> lock(mutex_);
  if (!ready_.wait_for(lock, std::chrono::milliseconds(timeout_ms), [this] { return !frames_.empty(); })) return false;
  *frame = frames_.front();
  frames_.pop_front();
  return true;
}

void InMemoryCanBus::Write(const CanFrame& frame) {
  std::lock_guard<std::mutex> lock(mutex_);
  written_.push_back(frame);
}

std::uint64_t InMemoryCanBus::error_frames() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return errors_;
}

std::vector<CanFrame> InMemoryCanBus::written() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return written_;
}

bool SocketCanAvailable(std::string* why) {
  const int fd = socket(PF_CAN, SOCK_RAW, CAN_RAW);
  if (fd < 0) {
    if (why) *why = SystemError("socket(PF_CAN, SOCK_RAW, CAN_RAW)") + " (the kernel has no CAN support)";
    return false;
  }
  close(fd);
  return true;
}

SocketCanBus::SocketCanBus(const std::string& interface) : interface_(interface) {
  if (interface.empty() || interface.size() >= IFNAMSIZ) throw std::runtime_error("CAN interface name '" + interface + "' is invalid");
  fd_ = socket(PF_CAN, SOCK_RAW, CAN_RAW);
  if (fd_ < 0) throw std::runtime_error(SystemError("CAN " + interface + ": socket(PF_CAN)"));
  ifreq ifr{};
  std::strncpy(ifr.ifr_name, interface.c_str(), IFNAMSIZ - 1);
  if (ioctl(fd_, SIOCGIFINDEX, &ifr) < 0) {
    const std::string e = SystemError("CAN " + interface + ": no such interface");
    close(fd_);
    throw std::runtime_error(e);
  }
  const int on = 1;
  setsockopt(fd_, SOL_CAN_RAW, CAN_RAW_FD_FRAMES, &on, sizeof on);  // classic-only interfaces refuse: fine
  const can_err_mask_t errors = CAN_ERR_MASK;
  setsockopt(fd_, SOL_CAN_RAW, CAN_RAW_ERR_FILTER, &errors, sizeof errors);
  sockaddr_can addr{};
  addr.can_family = AF_CAN;
  addr.can_ifindex = ifr.ifr_ifindex;
  if (bind(fd_, reinterpret_cast<sockaddr*>(&addr), sizeof addr) < 0) {
    const std::string e = SystemError("CAN " + interface + ": bind");
    close(fd_);
    throw std::runtime_error(e);
  }
  fcntl(fd_, F_SETFL, fcntl(fd_, F_GETFL) | O_NONBLOCK);
}

SocketCanBus::~SocketCanBus() {
  if (fd_ >= 0) close(fd_);
}

void SocketCanBus::SetFilters(const std::vector<CanId>& ids) {
  std::vector<can_filter> filters;
  for (const CanId& c : ids) {
    can_filter f{};
    f.can_id = c.extended ? (c.id | CAN_EFF_FLAG) : c.id;
    f.can_mask = (c.extended ? CAN_EFF_MASK : CAN_SFF_MASK) | CAN_EFF_FLAG | CAN_RTR_FLAG;
    filters.push_back(f);
  }
  if (setsockopt(fd_, SOL_CAN_RAW, CAN_RAW_FILTER, filters.empty() ? nullptr : filters.data(),
                 static_cast<socklen_t>(filters.size() * sizeof(can_filter))) < 0) {
    throw std::runtime_error(SystemError("CAN " + interface_ + ": setting filters"));
  }
}

bool SocketCanBus::Read(CanFrame* out, int timeout_ms) {
  pollfd p{fd_, POLLIN, 0};
  const int ready = poll(&p, 1, timeout_ms);
  if (ready < 0) {
    if (errno == EINTR) return false;
    throw std::runtime_error(SystemError("CAN " + interface_ + ": poll"));
  }
  if (ready == 0) return false;
  canfd_frame frame{};
  const ssize_t n = read(fd_, &frame, sizeof frame);
  if (n < 0) {
    if (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR) return false;
    throw std::runtime_error(SystemError("CAN " + interface_ + ": read"));
  }
  if (n != static_cast<ssize_t>(CAN_MTU) && n != static_cast<ssize_t>(CANFD_MTU)) return false;  // not a frame
  CanFrame f;
  f.t = Now();
  f.fd = n == static_cast<ssize_t>(CANFD_MTU);
  f.error = (frame.can_id & CAN_ERR_FLAG) != 0;
  f.extended = !f.error && (frame.can_id & CAN_EFF_FLAG) != 0;
  f.remote = !f.fd && (frame.can_id & CAN_RTR_FLAG) != 0;
  f.id = frame.can_id & (f.error ? CAN_ERR_MASK : (f.extended ? CAN_EFF_MASK : CAN_SFF_MASK));
  f.length = std::min<std::uint8_t>(frame.len, f.fd ? 64 : 8);
  f.fd_flags = f.fd ? frame.flags : 0;
  std::copy(frame.data, frame.data + f.length, f.data.begin());
  if (f.error) ++errors_;
  *out = f;
  return true;
}

void SocketCanBus::Write(const CanFrame& f) {
  canfd_frame frame{};
  frame.can_id = f.id | (f.extended ? CAN_EFF_FLAG : 0) | (f.remote ? CAN_RTR_FLAG : 0);
  frame.len = f.length;
  frame.flags = f.fd ? f.fd_flags : 0;
  std::copy(f.data.begin(), f.data.begin() + std::min<int>(f.length, 64), frame.data);
  const size_t size = f.fd ? CANFD_MTU : CAN_MTU;
  if (write(fd_, &frame, size) != static_cast<ssize_t>(size)) throw std::runtime_error(SystemError("CAN " + interface_ + ": write"));
}

}  // namespace inertial
